//! The cases, one module each, and the pieces they share.

pub mod bending_column_3d;
pub mod oscillating_plate_2d;
pub mod tl_common;
pub mod twisting_column_3d;

use crate::Case;

/// Every case, in the order `sph list` shows them.
pub static ALL: &[&dyn Case] = &[
    &oscillating_plate_2d::OscillatingPlate2d,
    &bending_column_3d::BendingColumn3d,
    &twisting_column_3d::TwistingColumn3d,
];
