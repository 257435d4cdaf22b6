//! Particle generators: exact lattice counts for the benchmark geometries (plates, columns, slabs)
//! whatever the round-off of `dp`, volumes that sum to the shape's measure, region tags for clamps
//! and supports, permutation, nearest particle, multi-body merging and input validation.

use glam::{DVec2, DVec3};
use sph_core::neighbor::invert_permutation;
use sph_core::{Error, D2, D3};
use sph_geometry::generate::{
    annulus_lattice, annulus_polar, hollow_sphere, hollow_sphere_polar, nearest_distances,
    tube_polar, Aabb, Annulus, Cylinder, HollowSphere, Lattice, ParticleSet, Shape,
};
use std::f64::consts::PI;

fn v2(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

fn v3(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn rect(min: DVec2, max: DVec2) -> Aabb<D2> {
    Aabb::new(min, max).unwrap()
}

fn cuboid(min: DVec3, max: DVec3) -> Aabb<D3> {
    Aabb::new(min, max).unwrap()
}

fn field_of(e: &Error) -> &str {
    match e {
        Error::InvalidParameter { field, .. } => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

/// Relative difference; volumes below are sums of at most ~1e5 equal terms, so exact to
/// ~n·ε ≈ 1e-11 at worst and usually far better.
fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn cantilever_plate_0p2_by_0p02_at_dp_0p002_has_exactly_1000_particles() {
    let (l, h, dp) = (0.2, 0.02, 0.002);
    let plate = rect(v2(0.0, -h / 2.0), v2(l, h / 2.0));
    let set = ParticleSet::fill(&Lattice::new(dp, v2(0.0, -h / 2.0)).unwrap(), &plate).unwrap();
    assert_eq!(set.len(), 1000);
    // Same count with the lattice anchored at the plate's centre line (y = 0 is a cell face
    // because H/dp is even).
    let set0 = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &plate).unwrap();
    assert_eq!(set0.len(), 1000);
    assert!(set.volumes().iter().all(|&v| v == dp * dp));
    // Tolerance 1e-12: a sum of 1000 equal terms (round-off ~1e-13 relative).
    assert!(rel(set.total_volume(), l * h) < 1e-12);
    let (lo, hi) = set.bounds().unwrap();
    assert!((lo - v2(dp / 2.0, -h / 2.0 + dp / 2.0)).abs().max_element() < 1e-15);
    assert!(
        (hi - v2(l - dp / 2.0, h / 2.0 - dp / 2.0))
            .abs()
            .max_element()
            < 1e-15
    );
}

#[test]
fn bending_column_counts_match_the_tl_paper_at_h_over_dp_6_12_24() {
    // CASES 5: column 1 × 1 × 6 m along z, 1,296 / 10,368 / 82,944 particles.
    let column = cuboid(v3(-0.5, -0.5, 0.0), v3(0.5, 0.5, 6.0));
    for (n, expected) in [(6, 1296), (12, 10_368), (24, 82_944)] {
        let dp = 1.0 / n as f64;
        let set =
            ParticleSet::fill(&Lattice::new(dp, v3(-0.5, -0.5, 0.0)).unwrap(), &column).unwrap();
        assert_eq!(set.len(), expected, "H/dp = {n}");
        // Anchoring at the global origin works too: ±0.5 and 6 are whole multiples of dp.
        let set0 = ParticleSet::fill(&Lattice::new(dp, DVec3::ZERO).unwrap(), &column).unwrap();
        assert_eq!(set0.len(), expected, "H/dp = {n}, origin 0");
        // Tolerance 1e-11: sum of up to 82,944 equal terms.
        assert!(rel(set.total_volume(), 6.0) < 1e-11);
        eprintln!("bending column H/dp = {n}: {} particles", set.len());
    }
}

#[test]
fn twisting_column_along_y_has_the_analytic_count_at_h_over_dp_4_8_10_12() {
    // CASES 6: same column with its axis along y.
    let column = cuboid(v3(-0.5, 0.0, -0.5), v3(0.5, 6.0, 0.5));
    for n in [4usize, 8, 10, 12] {
        let dp = 1.0 / n as f64;
        let set =
            ParticleSet::fill(&Lattice::new(dp, v3(-0.5, 0.0, -0.5)).unwrap(), &column).unwrap();
        assert_eq!(set.len(), n * n * 6 * n, "H/dp = {n}");
        eprintln!("twisting column H/dp = {n}: {} particles", set.len());
    }
}

#[test]
fn boundaries_on_cell_faces_give_exact_counts_at_awkward_spacings() {
    // dp = 0.1/7: 0.1/dp and 0.3/dp are 7 and 21 only up to round-off.
    let dp = 0.1 / 7.0;
    let r = rect(DVec2::ZERO, v2(0.1, 0.3));
    let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &r).unwrap();
    assert_eq!(set.len(), 7 * 21);
    let b = cuboid(DVec3::ZERO, v3(0.1, 0.2, 0.3));
    let set = ParticleSet::fill(&Lattice::new(dp, DVec3::ZERO).unwrap(), &b).unwrap();
    assert_eq!(set.len(), 7 * 14 * 21);
    // Sweep: plate 0.2 × 0.02 moved to an arbitrary place, H/dp = 1..=60 (every resolution a
    // case might use, including H/dp = 30 of UL Table 1): always (10 n) × n.
    let corner = v2(-0.37, 1.3);
    let plate = rect(corner, corner + v2(0.2, 0.02));
    for n in 1..=60usize {
        let dp = 0.02 / n as f64;
        let set = ParticleSet::fill(&Lattice::new(dp, corner).unwrap(), &plate).unwrap();
        assert_eq!(set.len(), 10 * n * n, "H/dp = {n}");
    }
    // CASES 15 slab 3 cm × 1 cm: (3n) × n for any n.
    let slab = rect(DVec2::ZERO, v2(0.03, 0.01));
    for n in [10usize, 31, 62, 97] {
        let dp = 0.01 / n as f64;
        let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &slab).unwrap();
        assert_eq!(set.len(), 3 * n * n, "slab H/dp = {n}");
    }
}

#[test]
fn box_volumes_are_exact_and_curved_volumes_converge_with_dp() {
    // Boxes: exactly the area/volume (tolerance: sum of n equal terms).
    let b = cuboid(v3(0.1, 0.2, 0.3), v3(0.5, 0.4, 0.31));
    let set = ParticleSet::fill(&Lattice::new(0.001, v3(0.1, 0.2, 0.3)).unwrap(), &b).unwrap();
    assert!(rel(set.total_volume(), b.measure()) < 1e-11);

    // Curved boundaries: only cells cut by the boundary can be misclassified, each by at most
    // one cell volume, so the worst case is a band about one cell wide along the boundary
    // (|ΔV| ≤ 2√d dp · perimeter or surface). A wrong layer or a shifted lattice produces an
    // error of that size; correct fills have errors of mixed sign that largely cancel. The test
    // therefore requires |ΔV| ≤ 0.1 dp · perimeter (surface): a band a tenth of a cell wide,
    // which halves with dp (shown at two resolutions; measured errors are printed).
    let ring = Annulus::new(DVec2::ZERO, 0.03, 0.04).unwrap();
    let perimeter = 2.0 * PI * (0.03 + 0.04);
    for dp in [0.002, 0.001] {
        let set = annulus_lattice(DVec2::ZERO, 0.03, 0.04, dp).unwrap();
        let err = (set.total_volume() - ring.area()).abs();
        let bound = 0.1 * dp * perimeter;
        eprintln!(
            "annulus 0.03/0.04 lattice dp = {dp}: {} particles, |ΔV|/V = {:.2e}, bound {:.2e}",
            set.len(),
            err / ring.area(),
            bound / ring.area()
        );
        assert!(err <= bound);
    }
    let shell = HollowSphere::new(DVec3::ZERO, 0.03, 0.04).unwrap();
    let surface = 4.0 * PI * (0.03f64.powi(2) + 0.04f64.powi(2));
    for dp in [0.002, 0.001] {
        let set = hollow_sphere(DVec3::ZERO, 0.03, 0.04, dp).unwrap();
        let err = (set.total_volume() - shell.volume()).abs();
        let bound = 0.1 * dp * surface;
        eprintln!(
            "hollow sphere 0.03/0.04 dp = {dp}: {} particles, |ΔV|/V = {:.2e}, bound {:.2e}",
            set.len(),
            err / shell.volume(),
            bound / shell.volume()
        );
        assert!(err <= bound);
        // Symmetric about the centre: the centroid is at the centre to round-off.
        let centroid = set.positions().iter().copied().sum::<DVec3>() / set.len() as f64;
        assert!(centroid.length() < 1e-15);
    }
    // CASES 4: pulling cylinder R = 1 mm, height 2 mm, dp = 0.1 mm; caps lie on cell faces, so
    // only the lateral surface counts in the bound.
    let (radius, height) = (1e-3, 2e-3);
    let cyl = Cylinder::new(DVec3::ZERO, DVec3::Z, radius, height).unwrap();
    for dp in [1e-4, 5e-5] {
        let set = ParticleSet::fill(&Lattice::new(dp, DVec3::ZERO).unwrap(), &cyl).unwrap();
        let err = (set.total_volume() - cyl.volume()).abs();
        let bound = 0.1 * dp * 2.0 * PI * radius * height;
        eprintln!(
            "cylinder R=1mm h=2mm dp = {dp}: {} particles, |ΔV|/V = {:.2e}, bound {:.2e}",
            set.len(),
            err / cyl.volume(),
            bound / cyl.volume()
        );
        assert!(err <= bound);
    }
}

#[test]
fn clamped_plate_built_from_rectangles_has_expected_counts_and_tags() {
    // CASES 1: plate of free length L continuing into a fixed base: 3 layers inside (x < 0)
    // and 3 layers above and below. H/dp = 10.
    let (l, h) = (0.2, 0.02);
    let dp = h / 10.0;
    let depth = 3.0 * dp;
    let plate = rect(v2(-depth, -h / 2.0), v2(l, h / 2.0));
    let base = rect(v2(-depth, -h / 2.0 - depth), v2(0.0, h / 2.0 + depth));
    let body = plate.union(base);
    let lattice = Lattice::new(dp, v2(0.0, -h / 2.0)).unwrap();
    let mut set = ParticleSet::fill(&lattice, &body).unwrap();
    // 100×10 free + 3×10 inside the base + 2 × 3×3 above and below.
    assert_eq!(set.len(), 1000 + 30 + 18);
    set.tag_region("clamp", &base).unwrap();
    assert_eq!(set.tagged("clamp").unwrap().len(), 48);
    let free = set.untagged("clamp").unwrap();
    assert_eq!(free.len(), 1000);
    assert!(free.iter().all(|&i| set.positions()[i as usize].x > 0.0));
    // The base without the plate (the frame that holds it) is a difference of rectangles.
    let frame = base.difference(plate);
    let frame_set = ParticleSet::fill(&lattice, &frame).unwrap();
    assert_eq!(frame_set.len(), 18);
    set.tag_region("frame", &frame).unwrap();
    assert_eq!(set.tagged("frame").unwrap().len(), 18);
    // Regions overlap: every frame particle is also a clamp particle.
    let clamp = set.tagged("clamp").unwrap();
    assert!(set
        .tagged("frame")
        .unwrap()
        .iter()
        .all(|i| clamp.contains(i)));
    assert_eq!(set.regions(), ["clamp".to_string(), "frame".to_string()]);
    // The free body alone, as a difference of the union and the base.
    let free_body = plate.union(base).difference(base);
    assert_eq!(ParticleSet::fill(&lattice, &free_body).unwrap().len(), 1000);

    // CASES 17 (MPS cantilever): free length 0.2 plus 0.04 held between bearings.
    let beam = rect(v2(-0.04, -h / 2.0), v2(l, h / 2.0));
    let mut mps = ParticleSet::fill(&lattice, &beam).unwrap();
    mps.tag_where("held", |_, x| x.x < 0.0).unwrap();
    assert_eq!(mps.len(), 1200);
    assert_eq!(mps.tagged("held").unwrap().len(), 200);
}

#[test]
fn simply_supported_plate_3d_tags_the_mid_thickness_lateral_lines() {
    // CASES 9: plate 0.4 × 0.4 × 0.01; at odd H/dp a particle layer lies at mid-thickness.
    let (l, h) = (0.4, 0.01);
    for n in [3usize, 5] {
        let dp = h / n as f64;
        let plate = cuboid(v3(0.0, 0.0, -h / 2.0), v3(l, l, h / 2.0));
        let mut set =
            ParticleSet::fill(&Lattice::new(dp, v3(0.0, 0.0, -h / 2.0)).unwrap(), &plate).unwrap();
        let m = (l / dp).round() as usize;
        assert_eq!(set.len(), m * m * n);
        set.tag_where("support", |_, x| {
            let side = x.x < dp || x.x > l - dp || x.y < dp || x.y > l - dp;
            side && x.z.abs() < 0.5 * dp
        })
        .unwrap();
        assert_eq!(set.tagged("support").unwrap().len(), 4 * m - 4);
        eprintln!(
            "3D plate H/dp = {n}: {} particles, {} supported",
            set.len(),
            4 * m - 4
        );
    }
}

#[test]
fn permute_round_trip_restores_every_field_and_tags_follow_particles() {
    let mut set = annulus_polar(DVec2::ZERO, 0.03, 0.04, 0.002).unwrap();
    set.tag_where("right", |_, x| x.x > 0.0).unwrap();
    let original = set.clone();
    let n = set.len();
    // A deterministic shuffle (LCG Fisher–Yates).
    let mut perm: Vec<u32> = (0..n as u32).collect();
    let mut s: u64 = 12345;
    for i in (1..n).rev() {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        perm.swap(i, (s >> 33) as usize % (i + 1));
    }
    set.permute(&perm).unwrap();
    for (new, &old) in perm.iter().enumerate() {
        assert_eq!(set.positions()[new], original.positions()[old as usize]);
        assert_eq!(set.volumes()[new], original.volumes()[old as usize]);
        assert_eq!(set.tags()[new], original.tags()[old as usize]);
    }
    assert!(set
        .tagged("right")
        .unwrap()
        .iter()
        .all(|&i| set.positions()[i as usize].x > 0.0));
    set.permute(&invert_permutation(&perm)).unwrap();
    assert_eq!(set, original);
    // Not a permutation: wrong length, repeated index, out of range.
    assert!(set.permute(&perm[1..]).is_err());
    let mut bad = perm.clone();
    bad[0] = bad[1];
    assert!(set.permute(&bad).is_err());
    bad[0] = n as u32;
    assert!(set.permute(&bad).is_err());
    assert_eq!(set, original, "a rejected permutation changes nothing");
}

#[test]
fn nearest_finds_the_closest_particle_and_breaks_ties_by_lowest_index() {
    let dp = 0.002;
    let plate = rect(v2(0.0, -0.01), v2(0.2, 0.01));
    let set = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &plate).unwrap();
    for i in [0usize, 17, 500, 999] {
        let x = set.positions()[i];
        assert_eq!(set.nearest(x), Some(i));
        assert_eq!(set.nearest(x + v2(0.3 * dp, -0.2 * dp)), Some(i));
    }
    // The mid-thickness tip (L, 0) is equidistant from (L − dp/2, ±dp/2): the lower-y one has the
    // lower index (first axis fastest, then y).
    let tip = set.nearest(v2(0.2, 0.0)).unwrap();
    let x = set.positions()[tip];
    assert!((x - v2(0.199, -0.001)).length() < 1e-15);
    assert_eq!(ParticleSet::<D2>::new().nearest(DVec2::ZERO), None);
}

#[test]
fn non_positive_dp_and_empty_fills_are_errors() {
    for dp in [0.0, -0.001, f64::NAN, f64::INFINITY] {
        let e = Lattice::<D2>::new(dp, DVec2::ZERO).unwrap_err();
        assert_eq!(field_of(&e), "dp");
        let e = Lattice::<D3>::new(dp, DVec3::ZERO).unwrap_err();
        assert_eq!(field_of(&e), "dp");
        let e = annulus_polar(DVec2::ZERO, 0.03, 0.04, dp).unwrap_err();
        assert_eq!(field_of(&e), "dp");
        let e = hollow_sphere(DVec3::ZERO, 0.03, 0.04, dp).unwrap_err();
        assert_eq!(field_of(&e), "dp");
    }
    // A box strictly between cell centres holds no particle.
    let dp = 0.01;
    let thin = rect(v2(0.1 * dp, 0.0), v2(0.4 * dp, 1.0));
    let e = ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &thin).unwrap_err();
    assert!(matches!(e, Error::EmptyBody { .. }), "{e:?}");
    // Disjoint intersection.
    let a = rect(DVec2::ZERO, v2(1.0, 1.0));
    let b = rect(v2(2.0, 2.0), v2(3.0, 3.0));
    let e =
        ParticleSet::fill(&Lattice::new(dp, DVec2::ZERO).unwrap(), &a.intersection(b)).unwrap_err();
    assert!(matches!(e, Error::EmptyBody { .. }), "{e:?}");
    // A spacing absurdly small for the shape is rejected, naming dp.
    let e = ParticleSet::fill(
        &Lattice::new(1e-9, DVec3::ZERO).unwrap(),
        &cuboid(DVec3::ZERO, DVec3::ONE),
    )
    .unwrap_err();
    assert_eq!(field_of(&e), "dp");
    // Invalid shapes name their field.
    assert_eq!(
        field_of(&Aabb::<D2>::new(DVec2::ONE, DVec2::ZERO).unwrap_err()),
        "max"
    );
    assert_eq!(
        field_of(&Annulus::new(DVec2::ZERO, 0.05, 0.04).unwrap_err()),
        "r_out"
    );
    assert_eq!(
        field_of(&Annulus::new(DVec2::ZERO, -0.01, 0.04).unwrap_err()),
        "r_in"
    );
    assert_eq!(
        field_of(&Cylinder::new(DVec3::ZERO, DVec3::ZERO, 1.0, 1.0).unwrap_err()),
        "axis"
    );
    // Unknown region names are errors, not empty lists.
    let set = annulus_polar(DVec2::ZERO, 0.03, 0.04, 0.002).unwrap();
    assert_eq!(field_of(&set.tagged("clmap").unwrap_err()), "region");
}

#[test]
fn annulus_polar_volumes_sum_to_the_ring_area() {
    // Tolerance 1e-12 relative: V_k = 2π r_k dr / n_k sums analytically to π(R² − r²); only
    // round-off of a few thousand terms remains.
    for (r_in, r_out, dp) in [
        (0.03, 0.04, 0.001),
        (0.03, 0.04, 0.0013),
        (0.0, 0.05, 0.0025),
        (0.1, 0.2, 0.1 / 7.0),
    ] {
        let set = annulus_polar(v2(0.5, -0.2), r_in, r_out, dp).unwrap();
        let area = PI * (r_out * r_out - r_in * r_in);
        assert!(
            rel(set.total_volume(), area) < 1e-12,
            "{r_in}/{r_out} dp {dp}: {} vs {area}",
            set.total_volume()
        );
        // Every particle lies in the ring and particles are not closer than ~dp: radial layers
        // are dr apart and on a ring of n_k = round(2πr/dp) the chord is ≥ dp(1 − 1/(2 n_k))·(1 −
        // small) — 0.8 dp leaves margin for the innermost, coarsest rings.
        let shape = Annulus::new(v2(0.5, -0.2), r_in, r_out).unwrap();
        assert!(set.positions().iter().all(|&x| shape.contains(x)));
        let mut min_d = f64::INFINITY;
        for (i, &a) in set.positions().iter().enumerate() {
            for &b in &set.positions()[i + 1..] {
                min_d = min_d.min((a - b).length());
            }
        }
        let dr = (r_out - r_in) / ((r_out - r_in) / dp).round();
        assert!(min_d >= 0.8 * dp.min(dr), "min distance {min_d} at dp {dp}");
        if r_in > 0.0 {
            assert!(set.tagged("inner").unwrap().iter().all(|&i| {
                ((set.positions()[i as usize] - v2(0.5, -0.2)).length() - r_in - dr / 2.0).abs()
                    < 1e-12
            }));
        }
        assert!(!set.tagged("outer").unwrap().is_empty());
        eprintln!(
            "annulus_polar {r_in}/{r_out} dp = {dp}: {} particles",
            set.len()
        );
    }
}

#[test]
fn tube_polar_volumes_sum_to_the_tube_volume_along_any_axis() {
    // CASES 7 stent tube cross-section: outer diameter 10 mm, wall 0.1 mm, dp = wall/3; a 2 mm
    // length (the stent is 20 mm) keeps the set at ~1.7e5 particles, far inside the generator's
    // memory budget on any machine (the full tube, 1.7e6 particles, was refused when other
    // processes held memory).
    let (r_out, wall, length) = (5e-3, 1e-4, 2e-3);
    let dp = wall / 3.0;
    let axis = v3(1.0, 2.0, 2.0);
    let base = v3(0.1, 0.2, 0.3);
    let set = tube_polar(base, axis, r_out - wall, r_out, length, dp).unwrap();
    let tube = Cylinder::tube(base, axis, r_out - wall, r_out, length).unwrap();
    // Tolerance 1e-10: ~1e5 terms summed.
    assert!(rel(set.total_volume(), tube.volume()) < 1e-10);
    // Points lie inside the tube (the ring radii are strictly inside the wall).
    assert!(set.positions().iter().all(|&x| tube.contains(x)));
    let inner = set.tagged("inner").unwrap().len();
    let outer = set.tagged("outer").unwrap().len();
    // Three layers: inner, middle, outer; the outer ring has more particles than the inner one.
    assert!(inner > 0 && outer > inner && inner + outer < set.len());
    eprintln!("stent tube dp = wall/3: {} particles", set.len());
}

#[test]
fn cylinder_bounds_enclose_a_tilted_cylinder() {
    let c = Cylinder::new(v3(1.0, -1.0, 0.5), v3(0.3, -0.5, 0.8), 0.2, 1.5).unwrap();
    let (lo, hi) = c.bounds();
    let set = ParticleSet::fill(&Lattice::new(0.02, DVec3::ZERO).unwrap(), &c).unwrap();
    let margin = 1e-12;
    assert!(set
        .positions()
        .iter()
        .all(|&x| x.cmpge(lo - margin).all() && x.cmple(hi + margin).all()));
    // Volume within a band a tenth of a cell wide (as for the other curved shapes; surface =
    // lateral + two caps).
    let surface = 2.0 * PI * 0.2 * 1.5 + 2.0 * PI * 0.04;
    assert!((set.total_volume() - c.volume()).abs() <= 0.1 * 0.02 * surface);
}

#[test]
fn extend_merges_bodies_and_regions_and_translate_moves_them() {
    // CASES 10: two rings, inner 0.03, outer 0.04, centres 0.09 apart.
    let mut left = annulus_polar(DVec2::ZERO, 0.03, 0.04, 0.002).unwrap();
    let n = left.len();
    let mut right = left.clone();
    left.tag_where("left", |_, _| true).unwrap();
    right.translate(v2(0.09, 0.0));
    right.tag_where("right", |_, _| true).unwrap();
    let mut scene = ParticleSet::<D2>::new();
    assert_eq!(scene.extend(&left).unwrap(), 0..n);
    assert_eq!(scene.extend(&right).unwrap(), n..2 * n);
    assert_eq!(scene.len(), 2 * n);
    assert_eq!(scene.regions(), ["inner", "outer", "left", "right"]);
    assert_eq!(
        scene.tagged("left").unwrap(),
        (0..n as u32).collect::<Vec<_>>()
    );
    assert_eq!(
        scene.tagged("right").unwrap(),
        (n as u32..2 * n as u32).collect::<Vec<_>>()
    );
    // "outer" holds both rings' outer layers.
    let outer_one = left.tagged("outer").unwrap().len();
    assert_eq!(scene.tagged("outer").unwrap().len(), 2 * outer_one);
    // Region bits are remapped when the other set orders its regions differently.
    let mut other = ParticleSet::fill(
        &Lattice::new(0.01, DVec2::ZERO).unwrap(),
        &rect(v2(1.0, 0.0), v2(1.1, 0.1)),
    )
    .unwrap();
    other.tag_where("right", |i, _| i == 0).unwrap();
    other.tag_where("new", |_, _| true).unwrap();
    let range = scene.extend(&other).unwrap();
    assert!(scene.is_tagged(range.start, "right"));
    assert!(!scene.is_tagged(range.start + 1, "right"));
    assert!(range.clone().all(|i| scene.is_tagged(i, "new")));
    assert!(
        rel(
            scene.total_volume(),
            2.0 * PI * (0.04f64.powi(2) - 0.03f64.powi(2)) + 0.01
        ) < 1e-12
    );
    // retain keeps tags with their particles.
    let removed = scene.retain(|_, x| x.x < 0.5);
    assert_eq!(removed, 100);
    assert_eq!(scene.len(), 2 * n);
    assert!(scene.tagged("new").unwrap().is_empty());
    assert_eq!(scene.tagged("right").unwrap().len(), n);
    // Too many regions is an error, not a silent overflow of the bit field.
    let mut crowded = ParticleSet::<D2>::new();
    for k in 0..32 {
        crowded.tag_where(&format!("r{k}"), |_, _| false).unwrap();
    }
    assert_eq!(
        field_of(&crowded.tag_where("r32", |_, _| false).unwrap_err()),
        "region"
    );
}

#[test]
fn from_parts_validates_lengths_and_values() {
    assert!(ParticleSet::<D2>::from_parts(vec![DVec2::ZERO], vec![]).is_err());
    assert!(ParticleSet::<D2>::from_parts(vec![DVec2::ZERO], vec![0.0]).is_err());
    assert!(ParticleSet::<D2>::from_parts(vec![DVec2::NAN], vec![1.0]).is_err());
    let set = ParticleSet::<D2>::from_parts(vec![DVec2::ZERO, DVec2::X], vec![1.0, 2.0]).unwrap();
    assert_eq!(set.masses(10.0), vec![10.0, 20.0]);
}

/// Mean, population standard deviation, minimum and maximum.
fn stats(v: &[f64]) -> (f64, f64, f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    let min = v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mean, sd, min, max)
}

#[test]
fn hollow_sphere_polar_volumes_sum_to_the_shell_volume_and_layers_are_spheres() {
    // Tolerance 1e-10 relative: each layer's volumes are its exact shell volume split evenly,
    // so only the round-off of summing ≤ 1.6e5 terms (≈ n ε ≈ 4e-11 at worst) remains.
    let c = v3(0.1, -0.2, 0.3);
    for (r_in, r_out, dp) in [
        (0.03, 0.04, 0.001),
        (0.03, 0.04, 0.0013),
        (0.0, 0.05, 0.005),
        (0.0, 0.05, 0.0025),
    ] {
        let set = hollow_sphere_polar(c, r_in, r_out, dp).unwrap();
        assert_eq!(set.spacing(), Some(dp));
        let exact = 4.0 / 3.0 * PI * (r_out.powi(3) - r_in.powi(3));
        assert!(
            rel(set.total_volume(), exact) < 1e-10,
            "{r_in}/{r_out} dp {dp}: {} vs {exact}",
            set.total_volume()
        );
        let nr = ((r_out - r_in) / dp).round();
        let dr = (r_out - r_in) / nr;
        // The outer layer is one sphere of radius r_out − dr/2 (to round-off): no staircase.
        for &i in &set.tagged("outer").unwrap() {
            let r = (set.positions()[i as usize] - c).length();
            assert!(
                (r - (r_out - 0.5 * dr)).abs() < 1e-12 * r_out,
                "outer r {r}"
            );
        }
        // Particle count ≈ shell volume / dp³ (the layers hold round(4π r²/dp²) points): 2 %.
        let n_expected = exact / (dp * dp * dp) * (dp / dr);
        assert!(
            (set.len() as f64 / n_expected - 1.0).abs() < 0.02,
            "{} particles vs {n_expected}",
            set.len()
        );
    }
}

#[test]
fn hollow_sphere_polar_is_evenly_spaced_and_balanced() {
    // The colliding balls of the UL paper (§6.4) at dp = 0.002 and a solid ball (Hertz case).
    for (r_in, r_out, dp) in [(0.03, 0.04, 0.002), (0.0, 0.05, 0.005)] {
        let set = hollow_sphere_polar(DVec3::ZERO, r_in, r_out, dp).unwrap();
        let d = nearest_distances::<D3>(set.positions(), 2.0 * dp).unwrap();
        let (mean, sd, min, max) = stats(&d);
        eprintln!(
            "hollow_sphere_polar {r_in}/{r_out} dp {dp}: {} particles, nearest distance / dp: \
             mean {:.3} sd {:.3} min {:.3} max {:.3}",
            set.len(),
            mean / dp,
            sd / dp,
            min / dp,
            max / dp
        );
        // Measured: mean 0.96/0.95 dp, sd 0.016 dp, min 0.87 dp, max 1.00 dp. Bounds with
        // margin: no pair closer than 0.8 dp, none farther than 1.1 dp, spread below 0.03 dp.
        assert!(min > 0.8 * dp && max < 1.1 * dp && sd < 0.03 * dp);
        // Balanced: the volume-weighted centroid sits at the centre (z exactly by the ±z
        // pairs; x, y to a small fraction of dp).
        let centroid = set
            .positions()
            .iter()
            .zip(set.volumes())
            .fold(DVec3::ZERO, |s, (&x, &v)| s + x * v)
            / set.total_volume();
        assert!(centroid.z.abs() < 1e-12 * r_out, "{centroid:?}");
        assert!(centroid.length() < 0.05 * dp, "{centroid:?}");
    }
    // The lattice cut of the same shell has a staircase surface: its outermost particles
    // spread over ≈ dp in radius; the layered one has none (checked exactly above).
    let (r_in, r_out, dp) = (0.03, 0.04, 0.002);
    let cut = hollow_sphere(DVec3::ZERO, r_in, r_out, dp).unwrap();
    let outer: Vec<f64> = cut
        .positions()
        .iter()
        .map(|x| x.length())
        .filter(|&r| r > r_out - dp)
        .collect();
    let (_, _, lo, hi) = stats(&outer);
    assert!(hi - lo > 0.5 * dp, "lattice surface spread {}", hi - lo);
}

/// Issue 14 item 3: a ring of `outer_radius = 1e300` (a count beyond every integer) and a lattice
/// fill far beyond the budget stop with `TooManyParticles` before allocating, not with a
/// capacity-overflow panic or an allocation abort; within the budget nothing changes.
#[test]
fn generators_refuse_counts_beyond_the_budget_before_allocating() {
    use sph_core::budget::{scoped, Budget, BYTES_PER_PARTICLE_2D, BYTES_PER_PARTICLE_3D};
    let too_many = |e: Error| match e {
        Error::TooManyParticles { what, limit, .. } => (what, limit),
        other => panic!("expected TooManyParticles, got {other:?}"),
    };
    scoped(Budget::unlimited(), || {
        let (what, _) = too_many(annulus_polar(v2(0.0, 0.0), 1.0, 1e300, 0.5).unwrap_err());
        assert!(what.contains("annulus_polar"), "{what}");
        too_many(
            tube_polar(v3(0.0, 0.0, 0.0), v3(0.0, 0.0, 1.0), 0.0, 1.0, 1e300, 0.1).unwrap_err(),
        );
        let (what, _) =
            too_many(hollow_sphere_polar(v3(0.0, 0.0, 0.0), 0.0, 1e300, 0.5).unwrap_err());
        assert!(what.contains("hollow_sphere_polar"), "{what}");
    });
    // 1,000 2D particles' worth of memory: a 100 × 100 square (10,000) does not fit; the error
    // comes after at most 1,000 kept points, with the estimate of the whole fill.
    scoped(
        Budget::with_limit(1_000 * BYTES_PER_PARTICLE_2D, "a test limit"),
        || {
            let lattice = Lattice::<D2>::new(0.01, v2(0.0, 0.0)).unwrap();
            let e = ParticleSet::fill(&lattice, &rect(v2(0.0, 0.0), v2(1.0, 1.0))).unwrap_err();
            let msg = e.to_string();
            let (_, limit) = too_many(e);
            assert!(limit.contains("a test limit"), "{limit}");
            // The estimate extrapolates from the share of candidates kept so far (the first
            // row of candidates is margin), so it is rough: within a factor 2 here.
            let estimate: f64 = msg
                .split("≈ ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .replace(',', "")
                .parse()
                .unwrap();
            assert!((5_000.0..20_000.0).contains(&estimate), "{msg}");
            // Two 30 × 30 squares: each fits, both together do not (the scope adds up).
            let small = rect(v2(0.0, 0.0), v2(0.3, 0.3));
            assert_eq!(ParticleSet::fill(&lattice, &small).unwrap().len(), 900);
            too_many(ParticleSet::fill(&lattice, &small).unwrap_err());
        },
    );
    scoped(
        Budget::with_limit(1_000 * BYTES_PER_PARTICLE_3D, "a test limit"),
        || {
            too_many(hollow_sphere(v3(0.0, 0.0, 0.0), 0.0, 1.0, 0.01).unwrap_err());
            assert!(hollow_sphere(v3(0.0, 0.0, 0.0), 0.0, 1.0, 0.25).is_ok());
            too_many(hollow_sphere_polar(v3(0.0, 0.0, 0.0), 0.0, 1.0, 0.01).unwrap_err());
            // The tetrahedron and round(4π r²/dp²) per layer: 4 + 28 + 79 + 154 = 265 particles at
            // dp = 0.25 fit beside the lattice ball above.
            assert!(hollow_sphere_polar(v3(0.0, 0.0, 0.0), 0.0, 1.0, 0.25).is_ok());
        },
    );
}

/// The surface detection of sph-core on the polar rings generated here (moved from sph-core's
/// unit tests with the generators).
mod surface_of_generated_sets {
    use sph_core::glam::DVec2;
    use sph_core::glam::DVec3;
    use sph_core::surface::surface_of;
    use sph_core::surface::thickness;
    use sph_core::D2;
    use sph_core::D3;
    use sph_geometry::generate::annulus_polar;
    use sph_geometry::generate::{Aabb, Lattice, ParticleSet};

    #[test]
    fn a_ring_has_its_inner_and_outer_layers_on_the_surface_with_radial_normals() {
        let set = annulus_polar(DVec2::ZERO, 1.0, 2.0, 0.1).unwrap();
        let all: Vec<u32> = (0..set.len() as u32).collect();
        let s = surface_of::<D2>(set.positions(), 0.1, &all).unwrap();
        let inner = set.tagged("inner").unwrap();
        let outer = set.tagged("outer").unwrap();
        assert_eq!(s.len(), inner.len() + outer.len());
        for p in &s {
            let x = set.positions()[p.index as usize];
            let radial = x.normalize();
            let sign = if inner.contains(&p.index) { -1.0 } else { 1.0 };
            // The polar layers are not exactly symmetric about each particle: within 2°.
            assert!(p.normal.dot(radial * sign) > 2f64.to_radians().cos(), "{x}");
        }
    }

    /// A lattice slab of an even or odd number of layers is exactly its height; a ring its
    /// wall, a ball its diameter (within a spacing: the surface layer of a curved body is not
    /// at exactly dp/2 from the surface).
    #[test]
    fn thickness_is_the_thinnest_extent_of_a_slab_the_wall_of_a_ring_the_diameter_of_a_ball() {
        let dp = 1.0;
        let lattice2 = Lattice::new(dp, DVec2::ZERO).unwrap();
        for layers in [1.0, 2.0, 3.0, 4.0, 7.0] {
            let b = Aabb::<D2>::new(DVec2::ZERO, DVec2::new(20.0, layers)).unwrap();
            let set = ParticleSet::fill(&lattice2, &b).unwrap();
            let t = thickness::<D2>(set.positions(), dp).unwrap();
            assert!((t - layers).abs() < 1e-9, "{layers} layers: {t}");
        }
        let b = Aabb::<D3>::new(DVec3::ZERO, DVec3::new(8.0, 5.0, 4.0)).unwrap();
        let set = ParticleSet::fill(&Lattice::new(dp, DVec3::ZERO).unwrap(), &b).unwrap();
        let t = thickness::<D3>(set.positions(), dp).unwrap();
        assert!((t - 4.0).abs() < 1e-9, "{t}");
        let ring = annulus_polar(DVec2::ZERO, 1.0, 2.0, 0.1).unwrap();
        let t = thickness::<D2>(ring.positions(), 0.1).unwrap();
        assert!((t - 1.0).abs() < 0.1, "ring wall: {t}");
        let disc = ParticleSet::fill(
            &Lattice::new(0.1, DVec2::splat(-1.0)).unwrap(),
            &sph_geometry::generate::FnShape::<D2, _>::new(
                (DVec2::splat(-1.0), DVec2::ONE),
                |x: DVec2| x.length() <= 1.0,
            ),
        )
        .unwrap();
        let t = thickness::<D2>(disc.positions(), 0.1).unwrap();
        assert!((t - 2.0).abs() < 0.1, "disc: {t}");
        assert!(thickness::<D2>(&[], dp).is_err());
        assert!(thickness::<D2>(&[DVec2::ZERO], 0.0).is_err());
    }
}
