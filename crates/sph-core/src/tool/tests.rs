use super::*;
use crate::amplitude::Amplitude;
use crate::dim::{D2, D3};
use crate::friction::Friction;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

#[test]
fn box_distance_is_signed_with_outward_normals() {
    let b = ToolShape::<D2>::cuboid(DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.5)).unwrap();
    let (d, n) = b.distance(DVec2::new(0.2, -0.3));
    assert!(
        (d - 0.3).abs() < 1e-15 && n == DVec2::new(0.0, -1.0),
        "{d} {n}"
    );
    let (d, n) = b.distance(DVec2::new(0.9, 0.25));
    assert!(
        (d + 0.1).abs() < 1e-15 && n == DVec2::new(1.0, 0.0),
        "{d} {n}"
    );
    // Corner: distance to the corner, normal from it.
    let (d, n) = b.distance(DVec2::new(1.3, 0.9));
    assert!((d - 0.5).abs() < 1e-15, "{d}");
    assert!((n - DVec2::new(0.6, 0.8)).length() < 1e-15, "{n}");
    assert!(ToolShape::<D2>::cuboid(DVec2::ONE, DVec2::ZERO).is_err());
}

#[test]
fn rounded_box_distance_is_the_sharp_ones_off_the_corners_and_a_circle_on_them() {
    let (min, max) = (DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.5));
    let b = ToolShape::<D2>::rounded_cuboid(min, max, 0.2).unwrap();
    let sharp = ToolShape::<D2>::cuboid(min, max).unwrap();
    // On a flat face, the sharp box's distance and normal.
    for x in [
        DVec2::new(0.2, -0.3),
        DVec2::new(0.9, 0.25),
        DVec2::new(-0.5, 0.7),
    ] {
        let ((d, n), (e, m)) = (b.distance(x), sharp.distance(x));
        assert!(
            (d - e).abs() < 1e-15 && (n - m).length() < 1e-15,
            "{x}: {d} {e}"
        );
    }
    // Beyond a corner: the distance to the circle of radius 0.2 about (0.8, 0.3).
    let x = DVec2::new(1.3, 0.9);
    let c = DVec2::new(0.8, 0.3);
    let (d, n) = b.distance(x);
    assert!((d - ((x - c).length() - 0.2)).abs() < 1e-15, "{d}");
    assert!((n - (x - c).normalize()).length() < 1e-15, "{n}");
    // The corner point of the sharp box is outside the rounded one.
    assert!(b.distance(max).0 > 0.0 && sharp.distance(max).0 == 0.0);
    assert_eq!(
        ToolShape::<D2>::rounded_cuboid(min, max, 0.0).unwrap(),
        sharp
    );
    assert!(
        ToolShape::<D2>::rounded_cuboid(min, max, 0.3).is_err(),
        "> half a side"
    );
    assert!(ToolShape::<D2>::rounded_cuboid(min, max, -0.1).is_err());
    assert_eq!(b.bounds(), (min, max));
}

#[test]
fn ball_and_half_space_distances() {
    let s = ToolShape::<D3>::ball(DVec3::ZERO, 2.0).unwrap();
    let (d, n) = s.distance(DVec3::new(0.0, 3.0, 0.0));
    assert!((d - 1.0).abs() < 1e-15 && n == DVec3::Y);
    let w = ToolShape::<D3>::half_space(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0)).unwrap();
    assert_eq!(w.distance(DVec3::new(5.0, 1.0, -0.25)), (-0.25, DVec3::Z));
    assert!(ToolShape::<D3>::half_space(DVec3::ZERO, DVec3::ZERO).is_err());
    assert!(ToolShape::<D3>::ball(DVec3::ZERO, 0.0).is_err());
}

#[test]
fn motion_ramps_smoothly_and_stops_at_its_travel() {
    let m = ToolMotion::<D2>::new(DVec2::new(0.0, -2.0), 3.0, 0.5, 1.0).unwrap();
    assert_eq!(m.velocity(0.0), DVec2::ZERO);
    // Mid-ramp speed is half the final speed; distance is the integral of the speed.
    assert!((m.velocity(0.25).y + 1.5).abs() < 1e-12);
    let ramp = m.distance(0.5);
    assert!((ramp - 0.75).abs() < 1e-12, "{ramp}");
    let h = 1e-6;
    let fd = (m.distance(0.3 + h) - m.distance(0.3 - h)) / (2.0 * h);
    assert!((fd - m.velocity(0.3).length()).abs() < 1e-8);
    let t_stop = m.arrival_time();
    assert!((t_stop - (0.5 + 0.25 / 3.0)).abs() < 1e-12, "{t_stop}");
    assert_eq!(m.distance(10.0), 1.0);
    assert_eq!(m.velocity(t_stop + 1e-9), DVec2::ZERO);
    assert_eq!(m.displacement(10.0), DVec2::new(0.0, -1.0));
    // A stop inside the ramp.
    let m = ToolMotion::<D2>::new(DVec2::X, 1.0, 1.0, 0.1).unwrap();
    assert!((m.distance(m.arrival_time()) - 0.1).abs() < 1e-12);
    assert!(ToolMotion::<D2>::new(DVec2::ZERO, 1.0, 0.0, 1.0).is_err());
    assert!(ToolMotion::<D2>::new(DVec2::X, 1.0, 0.0, 0.0).is_err());
}

#[test]
fn paths_and_velocity_curves_give_their_displacements() {
    let p = ToolMotion::<D2>::path(vec![
        (0.0, DVec2::ZERO),
        (1.0, DVec2::new(0.0, -2.0)),
        (3.0, DVec2::new(4.0, -2.0)),
    ])
    .unwrap();
    assert_eq!(p.displacement(-1.0), DVec2::ZERO);
    assert_eq!(p.displacement(0.5), DVec2::new(0.0, -1.0));
    assert_eq!(p.displacement(2.0), DVec2::new(2.0, -2.0));
    assert_eq!(p.displacement(9.0), DVec2::new(4.0, -2.0));
    assert_eq!(p.velocity(0.5), DVec2::new(0.0, -2.0));
    assert_eq!(p.velocity(2.0), DVec2::new(2.0, 0.0));
    assert_eq!(p.velocity(3.5), DVec2::ZERO);
    assert_eq!((p.arrival_time(), p.distance(2.0)), (3.0, 8f64.sqrt()));
    assert!(!p.is_straight());
    assert!(ToolMotion::<D2>::path(vec![(1.0, DVec2::ZERO), (1.0, DVec2::X)]).is_err());
    assert!(ToolMotion::<D2>::path(Vec::new()).is_err());
    let ramp = Amplitude::ramp(0.0, 2.0).unwrap();
    let v = ToolMotion::<D2>::translating(DVec2::new(3.0, 0.0), Some(ramp)).unwrap();
    // ∫₀¹ t/2 dt = 1/4; after the ramp 1 + (t − 2).
    assert_eq!(v.displacement(1.0), DVec2::new(0.75, 0.0));
    assert_eq!(v.displacement(3.0), DVec2::new(6.0, 0.0));
    assert_eq!(v.velocity(1.0), DVec2::new(1.5, 0.0));
    assert!(ToolMotion::<D2>::translating(DVec2::new(f64::NAN, 0.0), None).is_err());
}

#[test]
fn a_rotating_tool_turns_its_shape_and_normals_about_the_centre() {
    // A paddle [1, 2] × [−0.1, 0.1] turning about the origin at π/2 rad/s: after 1 s it
    // stands along +y.
    let shape = ToolShape::<D2>::cuboid(DVec2::new(1.0, -0.1), DVec2::new(2.0, 0.1)).unwrap();
    let motion = ToolMotion::fixed()
        .rotating(DVec2::ZERO, DVec3::Z, 0.5 * PI, None)
        .unwrap();
    let tool = RigidTool::new("paddle", shape, motion);
    assert!((tool.motion.angle(1.0) - 0.5 * PI).abs() < 1e-15);
    // The point (0, 1.5) is inside the turned paddle, 0.1 from its face at x = −0.1 whose
    // outward normal is −x (tolerance: round-off of cos(π/2)).
    let (d, n) = tool.distance_at(DVec2::new(0.0, 1.5), 1.0);
    assert!((d + 0.1).abs() < 1e-12, "{d}");
    let (d, n2) = tool.distance_at(DVec2::new(-0.3, 1.5), 1.0);
    assert!((d - 0.2).abs() < 1e-12 && (n - n2).length() < 1e-12, "{d}");
    assert!((n - DVec2::new(-1.0, 0.0)).length() < 1e-12, "{n}");
    // Contact pushes a particle in the paddle's way along the turned normal.
    let x = vec![DVec2::new(-0.05, 1.5)];
    let mut v = vec![DVec2::ZERO];
    let out = tool.enforce_contact(1.0, 0.01, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true]);
    assert_eq!(out.active, 1);
    assert!(v[0].x < 0.0 && v[0].y.abs() < 1e-9, "{:?}", v[0]);
    // 3D: a quarter turn about z through (1, 0, 0) takes (2, 0, 0) to (1, 1, 0).
    let r = rotation_matrix::<D3>(DVec3::Z, 0.5 * PI);
    let y = DVec3::X + r * (DVec3::new(2.0, 0.0, 0.0) - DVec3::X);
    assert!((y - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-15, "{y}");
    // In 2D only the z axis.
    assert!(ToolMotion::<D2>::fixed()
        .rotating(DVec2::ZERO, DVec3::X, 1.0, None)
        .is_err());
}

#[test]
fn a_corner_radius_of_half_the_side_is_accepted_when_the_corners_round_off() {
    // (1.5e-3 + 3e-4) − 1.5e-3 = 2.9999999999999992e-4: half of it is below 1.5e-4.
    let (h, t) = (1.5e-3, 3e-4);
    let min = DVec2::new(-4.5e-3, h);
    let max = DVec2::new(4.5e-3, h + t);
    assert!((max.y - min.y) * 0.5 < 1.5e-4);
    let s = ToolShape::<D2>::rounded_cuboid(min, max, 1.5e-4).unwrap();
    let ToolShape::RoundedBox { radius, .. } = s else {
        panic!("{s:?}")
    };
    assert_eq!(radius, 0.5 * (max.y - min.y));
    // Beyond round-off it is still refused.
    assert!(ToolShape::<D2>::rounded_cuboid(min, max, 1.51e-4).is_err());
}

#[test]
fn contact_puts_particles_on_the_offset_surface_along_the_normal_only() {
    // A platen whose lower face is at y = 0 moving down at 1 m/s; three particles below.
    let shape = ToolShape::<D2>::cuboid(DVec2::new(-1.0, 0.0), DVec2::new(1.0, 1.0)).unwrap();
    let motion = ToolMotion::new(DVec2::new(0.0, -1.0), 1.0, 0.0, f64::INFINITY).unwrap();
    let tool = RigidTool::new("punch", shape, motion);
    let x = vec![
        DVec2::new(0.0, -0.7),
        DVec2::new(0.5, -0.45),
        DVec2::new(3.0, -0.45),
    ];
    let mut v = vec![DVec2::new(0.3, 0.0), DVec2::new(-0.2, 0.1), DVec2::ZERO];
    let m = vec![2.0, 1.0, 1.0];
    let (t_end, drift, offset) = (0.1, 0.05, 0.5);
    let out = tool.enforce_contact(
        t_end,
        drift,
        |_, _| offset,
        offset,
        &x,
        &mut v,
        &m,
        &[true; 3],
    );
    // Particle 0 ends at -0.7, clear of the offset surface at -0.1 - 0.5 = -0.6. Particle 1
    // would end at -0.445, above the offset surface at -0.6: pushed down to land on it.
    assert_eq!(out.active, 1);
    assert_eq!(v[0], DVec2::new(0.3, 0.0));
    let end = x[1] + v[1] * drift;
    assert!((end.y + 0.6).abs() < 1e-14, "{end}");
    // Tangential velocity untouched (frictionless), impulse along the normal only.
    assert_eq!(v[1].x, -0.2);
    assert!((out.impulse.y - m[1] * (v[1].y - 0.1)).abs() < 1e-14);
    assert_eq!(out.impulse.x, 0.0);
    // Far particle: untouched.
    assert_eq!(v[2], DVec2::ZERO);
}

#[test]
fn friction_sticks_within_the_static_cone_and_slides_on_the_kinetic_one() {
    // A floor at y = 0 at rest; one particle pressed into it at 1 m/s, sliding along it.
    let floor = ToolShape::<D2>::half_space(DVec2::ZERO, DVec2::Y).unwrap();
    let tool = RigidTool::new("floor", floor, ToolMotion::fixed())
        .with_friction(Friction::new(0.5, 0.2).unwrap());
    let x = vec![DVec2::new(0.0, 0.0)];
    let (tau, m) = (0.1, [2.0]);
    // Slides at 0.4 ≤ μ_s · 1: stuck.
    let mut v = vec![DVec2::new(0.4, -1.0)];
    let out = tool.enforce_contact(tau, tau, |_, _| 0.0, 0.0, &x, &mut v, &m, &[true]);
    assert_eq!((out.active, out.sticking), (1, 1));
    assert!(v[0].length() < 1e-15, "{}", v[0]);
    // The friction impulse is what stopped the slide; the work is the kinetic energy lost.
    assert!((out.friction_impulse - DVec2::new(-0.8, 0.0)).length() < 1e-15);
    assert!((out.impulse - DVec2::new(-0.8, 2.0)).length() < 1e-15);
    let ke = 0.5 * 2.0 * (0.4f64.powi(2) + 1.0);
    assert!((out.normal_work + out.friction_work + ke).abs() < 1e-15);
    assert!((out.friction_dissipation + out.friction_work).abs() < 1e-15);
    // Slides at 0.9 > μ_s · 1: slowed by μ_k · 1.
    let mut v = vec![DVec2::new(-0.9, -1.0)];
    let out = tool.enforce_contact(tau, tau, |_, _| 0.0, 0.0, &x, &mut v, &m, &[true]);
    assert_eq!((out.active, out.sticking), (1, 0));
    assert!((v[0] - DVec2::new(-0.7, 0.0)).length() < 1e-15, "{}", v[0]);
    assert!(out.friction_dissipation > 0.0);
}

#[test]
fn a_moving_tool_drags_what_sticks_to_it_and_does_work_through_friction() {
    // A belt (the floor moving at 2 m/s along x) under a particle at rest pressed into it.
    let floor = ToolShape::<D3>::half_space(DVec3::ZERO, DVec3::Z).unwrap();
    let belt = ToolMotion::translating(DVec3::new(2.0, 0.0, 0.0), None).unwrap();
    let tool = RigidTool::new("belt", floor, belt).with_friction(Friction::new(1.0, 1.0).unwrap());
    let x = vec![DVec3::ZERO];
    let mut v = vec![DVec3::new(0.0, 0.0, -3.0)];
    let out = tool.enforce_contact(1.0, 0.5, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true]);
    // Relative slip 2 m/s ≤ μ_s · 3: it sticks, moving with the belt.
    assert_eq!(out.sticking, 1);
    assert!(
        (v[0] - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-12,
        "{}",
        v[0]
    );
    // The belt did positive work on it (½ m 2²); the dissipation is what the slip lost.
    assert!(
        (out.friction_work - 2.0).abs() < 1e-12,
        "{}",
        out.friction_work
    );
    assert!(
        (out.friction_dissipation - 2.0).abs() < 1e-12,
        "{}",
        out.friction_dissipation
    );
    // A turning tool: a disc of radius 1 spinning at 1 rad/s about its centre drags a
    // particle sticking to its rim at the rim's speed, tangentially.
    let disc = ToolShape::<D2>::ball(DVec2::ZERO, 1.0).unwrap();
    let spin = ToolMotion::fixed()
        .rotating(DVec2::ZERO, DVec3::Z, 1.0, None)
        .unwrap();
    let tool = RigidTool::new("disc", disc, spin).with_friction(Friction::new(1.0, 1.0).unwrap());
    let x = vec![DVec2::new(0.0, 1.0)];
    let mut v = vec![DVec2::new(0.0, -2.0)];
    let tau = 1e-6;
    let out = tool.enforce_contact(tau, tau, |_, _| 0.0, 0.0, &x, &mut v, &[1.0], &[true]);
    assert_eq!(out.sticking, 1);
    assert!((v[0] - DVec2::new(-1.0, 0.0)).length() < 1e-5, "{}", v[0]);
}

#[test]
fn a_tool_set_meters_the_friction_and_keeps_series_columns_of_frictionless_tools() {
    let floor = ToolShape::<D2>::half_space(DVec2::ZERO, DVec2::Y).unwrap();
    let plain = RigidTool::new("plain", floor.clone(), ToolMotion::fixed());
    let rough = RigidTool::new("rough", floor.clone(), ToolMotion::fixed())
        .with_friction(Friction::new(0.3, 0.3).unwrap());
    let mut set = ToolSet::new(vec![plain.clone(), rough], &[], 10.0).unwrap();
    assert!(set.has_friction());
    assert_eq!(
        set.series()[0].columns,
        ["displacement", "force_x", "force_y", "contacts"]
    );
    assert_eq!(
        set.series()[1].columns,
        [
            "displacement",
            "force_x",
            "force_y",
            "contacts",
            "friction_x",
            "friction_y",
            "sticking"
        ]
    );
    // Two particles sliding into the floors: the first tool takes all the normal
    // velocity, the second none (already on the surface), so no friction there.
    let x = vec![DVec2::ZERO, DVec2::new(1.0, 0.0)];
    let mut v = vec![DVec2::new(1.0, -1.0), DVec2::new(0.1, -1.0)];
    set.begin_step();
    set.enforce(
        0.5,
        0.5,
        |_, _| 0.0,
        0.0,
        &x,
        &mut v,
        &[1.0, 1.0],
        &[true, true],
        true,
    );
    set.end_step(0.5);
    set.record(0.5);
    assert_eq!(set.contacts(), &[2, 0]);
    let s = &set.series()[0];
    assert_eq!(s.column("force_y").unwrap()[1], -4.0);
    assert_eq!(set.series()[1].column("friction_x").unwrap()[1], 0.0);
    // Names are checked, and a tool must be slower than sound.
    assert!(ToolSet::new(vec![plain.clone(), plain.clone()], &[], 10.0).is_err());
    assert!(ToolSet::new(vec![plain.clone()], &["plain"], 10.0).is_err());
    let fast = RigidTool::new(
        "fast",
        floor,
        ToolMotion::translating(DVec2::new(20.0, 0.0), None).unwrap(),
    );
    assert!(ToolSet::new(vec![fast], &[], 10.0).is_err());
    // Its state round-trips through a checkpoint.
    let mut out = crate::StateWriter::default();
    set.save(&mut out);
    let bytes = out.into_bytes();
    let mut back = ToolSet::new(set.tools().to_vec(), &[], 10.0).unwrap();
    back.restore(&mut crate::StateReader::new(&bytes)).unwrap();
    assert_eq!(back.work(), set.work());
    assert_eq!(back.series(), set.series());
}

#[test]
fn reaction_meter_averages_over_the_interval() {
    let mut r = ReactionMeter::<D2>::default();
    r.add(DVec2::new(1.0, 0.0), 1.0);
    r.add(DVec2::new(4.0, 2.0), 3.0);
    assert_eq!(r.take_mean(), DVec2::new(3.25, 1.5));
    assert_eq!(r.take_mean(), DVec2::new(4.0, 2.0));
}

/// A surface given through [`SignedDistance`]: here the exact ball, so that the `Surface`
/// variant's plumbing (motion, bounds, contact, friction) can be compared bit for bit with the
/// `Ball` variant's.
#[derive(Debug)]
struct BallSurface(ToolShape<D3>);

impl SignedDistance<D3> for BallSurface {
    fn signed_distance(&self, x: DVec3) -> (f64, DVec3) {
        self.0.distance(x)
    }
    fn bounds(&self) -> (DVec3, DVec3) {
        self.0.bounds()
    }
}

#[test]
fn a_surface_tool_moves_and_touches_exactly_as_the_primitive_it_describes() {
    let ball = ToolShape::<D3>::ball(DVec3::new(0.1, 0.0, 0.3), 0.2).unwrap();
    let surface = ToolShape::<D3>::surface(std::sync::Arc::new(BallSurface(ball.clone()))).unwrap();
    assert_eq!(surface.bounds(), ball.bounds());
    assert_eq!(surface, surface.clone(), "a clone shares the surface");
    assert_ne!(surface, ball);
    // Translating down and turning about an off-centre axis, with friction.
    let motion = ToolMotion::<D3>::new(DVec3::new(0.0, 0.0, -1.0), 0.5, 0.0, f64::INFINITY)
        .unwrap()
        .rotating(
            DVec3::new(0.0, 0.1, 0.3),
            DVec3::new(1.0, 1.0, 0.0).normalize(),
            2.0,
            None,
        )
        .unwrap();
    let friction = Friction::new(0.4, 0.3).unwrap();
    let tools: Vec<RigidTool<D3>> = [ball, surface]
        .into_iter()
        .map(|s| RigidTool::new("t", s, motion.clone()).with_friction(friction))
        .collect();
    assert_eq!(tools[0].max_speed(), tools[1].max_speed());
    // A cloud of particles about the ball's path, some of them inside at t = 0.1.
    let x: Vec<DVec3> = (0..400)
        .map(|i| {
            let f = i as f64;
            DVec3::new(
                0.1 + 0.25 * (0.37 * f).sin(),
                0.25 * (0.91 * f).cos(),
                0.25 + 0.25 * (0.53 * f).sin(),
            )
        })
        .collect();
    let v0: Vec<DVec3> = (0..400)
        .map(|i| DVec3::new(0.0, 0.1 * (i as f64).sin(), 0.2))
        .collect();
    let (m, movable) = (vec![1e-3; 400], vec![true; 400]);
    let mut outcomes = Vec::new();
    let mut velocities = Vec::new();
    for tool in &tools {
        let mut v = v0.clone();
        let out = tool.enforce_contact(0.1, 0.01, |_, _| 0.01, 0.01, &x, &mut v, &m, &movable);
        for p in &x {
            assert_eq!(tools[0].distance_at(*p, 0.1), tool.distance_at(*p, 0.1));
        }
        outcomes.push(out);
        velocities.push(v);
    }
    assert!(
        outcomes[0].active > 10 && outcomes[0].sticking > 0,
        "{:?}",
        outcomes[0]
    );
    assert_eq!(outcomes[0], outcomes[1]);
    assert_eq!(velocities[0], velocities[1]);
}
