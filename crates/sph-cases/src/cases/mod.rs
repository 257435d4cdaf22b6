//! The cases, one module each, and the pieces they share.

pub mod ball_plate;
pub mod bending_column_3d;
pub mod cantilever_plate_2d;
pub mod colliding_balls_3d;
pub mod colliding_rings_2d;
pub mod folding_strip;
pub mod hertz_impact_3d;
pub mod impact_common;
pub mod incline_block;
pub mod mps_common;
pub mod oscillating_plate_2d;
pub mod oscillating_plate_3d;
pub mod pressurised_ring_2d;
pub mod pulling_cylinder_3d;
pub mod pulling_strip_2d;
pub mod punching_strip_2d;
pub mod quasi_static;
pub mod slab_tension_2d;
pub mod static_cantilever_2d;
pub mod stent_3d;
pub mod taylor_bar_3d;
pub mod tl_common;
pub mod twisting_column_3d;
pub mod ul_common;

use crate::Case;

/// Every case, in the order `sph list` shows them.
pub static ALL: &[&dyn Case] = &[
    &oscillating_plate_2d::OscillatingPlate2d,
    &oscillating_plate_3d::OscillatingPlate3d,
    &bending_column_3d::BendingColumn3d,
    &twisting_column_3d::TwistingColumn3d,
    &punching_strip_2d::PunchingStrip2d,
    &pulling_strip_2d::PullingStrip2d,
    &pulling_cylinder_3d::PullingCylinder3d,
    &stent_3d::Stent3d,
    &pressurised_ring_2d::PressurisedRing2d,
    &slab_tension_2d::SlabTension2d,
    &colliding_rings_2d::CollidingRings2d,
    &colliding_balls_3d::CollidingBalls3d,
    &ball_plate::BallPlate2d,
    &ball_plate::BallPlate3d,
    &hertz_impact_3d::HertzImpact3d,
    &taylor_bar_3d::TaylorBar3d,
    &cantilever_plate_2d::CantileverPlate2d,
    &static_cantilever_2d::StaticCantilever2d,
    &incline_block::InclineBlock,
    &folding_strip::FoldingStrip,
];
