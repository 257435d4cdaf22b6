//! Polar generators (rings, tubes and spheres in concentric layers, with smooth curved
//! surfaces) and the lattice fills of rings and spheres.

use super::*;

/// Layer radii of a ring `[r_in, r_out]` split into `n = max(1, round((r_out − r_in)/dp))`
/// layers of equal thickness `dr`; returns `(dr, radii at layer mid-lines)`.
fn ring_layers(r_in: f64, r_out: f64, dp: f64) -> (f64, Vec<f64>) {
    let n = ((r_out - r_in) / dp).round().max(1.0) as usize;
    let dr = (r_out - r_in) / n as f64;
    (dr, (0..n).map(|k| r_in + (k as f64 + 0.5) * dr).collect())
}

/// The particle count of [`annulus_polar`] without generating it: `n_r` layers of
/// `max(1, 2π r_k/dp)` particles, summed in closed form (within `n_r/2` of the exact count of
/// the rounded layers; any input, also one whose count overflows every integer, is safe).
fn ring_particle_estimate(r_in: f64, r_out: f64, dp: f64) -> f64 {
    let layers = ((r_out - r_in) / dp).round().max(1.0);
    let mid = 0.5 * (r_in + r_out);
    layers * (2.0 * PI * mid / dp).max(1.0) + 0.5 * layers
}

/// The particle count of [`hollow_sphere_polar`] without generating it: `n_r` layers of
/// `max(1, 4π r_k²/dp²)` particles, `Σ r_k² = n_r r_mid² + dr² n_r (n_r² − 1)/12` in closed
/// form, plus the central tetrahedron (within `n_r/2 + 4` of the exact count of the rounded
/// layers; any input, also one whose count overflows every integer, is safe).
fn sphere_particle_estimate(r_in: f64, r_out: f64, dp: f64) -> f64 {
    let layers = ((r_out - r_in) / dp).round().max(1.0);
    let dr = (r_out - r_in) / layers;
    let mid = 0.5 * (r_in + r_out);
    let sum_r2 = layers * mid * mid + dr * dr * layers * (layers * layers - 1.0) / 12.0;
    (4.0 * PI * sum_r2 / (dp * dp)).max(layers) + 0.5 * layers + 4.0
}

/// A 2D ring `r_in ≤ r ≤ r_out` in concentric layers, for bodies whose curved surfaces should be
/// smooth (rings, pressurised ring).
///
/// The ring is split into `n_r = max(1, round((r_out − r_in)/dp))` layers of thickness
/// `dr = (r_out − r_in)/n_r` (`= dp` when the wall is a whole number of spacings). Layer `k` has
/// `n_k = max(1, round(2π r_k / dp))` particles evenly spaced on the circle of radius
/// `r_k = r_in + (k + ½) dr`, starting at angle 0 on even layers and half a spacing later on odd
/// layers. Each particle of layer `k` has the volume of its share of the layer,
/// `V = 2π r_k dr / n_k`, so the volumes sum to `π (r_out² − r_in²)` up to round-off.
/// Regions: `"outer"` (layer `n_r − 1`) and, if `r_in > 0`, `"inner"` (layer 0).
pub fn annulus_polar(
    centre: DVec2,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D2>, Error> {
    check_positive("dp", dp)?;
    check_radii(r_in, r_out)?;
    if !centre.is_finite() {
        return Err(Error::invalid("centre", centre, "finite"));
    }
    budget::reserve::<D2>(
        ring_particle_estimate(r_in, r_out, dp),
        &format!("annulus_polar at dp = {dp:?}"),
    )?;
    let (dr, radii) = ring_layers(r_in, r_out, dp);
    let mut positions = Vec::new();
    let mut volumes = Vec::new();
    let mut layer = Vec::new();
    for (k, &r) in radii.iter().enumerate() {
        let n = (2.0 * PI * r / dp).round().max(1.0) as usize;
        let v = 2.0 * PI * r * dr / n as f64;
        let phase = if k % 2 == 1 { 0.5 } else { 0.0 };
        for j in 0..n {
            let theta = 2.0 * PI * (j as f64 + phase) / n as f64;
            let (s, c) = theta.sin_cos();
            positions.push(centre + DVec2::new(c, s) * r);
            volumes.push(v);
            layer.push(k);
        }
    }
    let mut set = ParticleSet::from_parts(positions, volumes)?.with_spacing(dp);
    let last = radii.len() - 1;
    if r_in > 0.0 {
        set.tag_where("inner", |i, _| layer[i] == 0)?;
    }
    set.tag_where("outer", |i, _| layer[i] == last)?;
    Ok(set)
}

/// A 3D tube (or solid cylinder if `r_in = 0`) as [`annulus_polar`] rings stacked along `axis`:
/// `n_z = max(1, round(length/dp))` slices of thickness `dz = length/n_z` centred at
/// `base + (m + ½) dz axis`; `V = 2π r_k dr dz / n_k`, summing to `π (r_out² − r_in²) length`.
/// Regions `"outer"` and (if `r_in > 0`) `"inner"` as in [`annulus_polar`].
pub fn tube_polar(
    base: DVec3,
    axis: DVec3,
    r_in: f64,
    r_out: f64,
    length: f64,
    dp: f64,
) -> Result<ParticleSet<D3>, Error> {
    check_positive("length", length)?;
    if !base.is_finite() {
        return Err(Error::invalid("base", base, "finite"));
    }
    let axis = axis
        .try_normalize()
        .ok_or_else(|| Error::invalid("axis", axis, "finite and non-zero"))?;
    check_positive("dp", dp)?;
    check_radii(r_in, r_out)?;
    let slices = (length / dp).round().max(1.0);
    budget::reserve::<D3>(
        slices * ring_particle_estimate(r_in, r_out, dp),
        &format!("tube_polar at dp = {dp:?}"),
    )?;
    // The ring itself is a 2D set of one slice's size: booked only through the tube above.
    let ring = budget::scoped(budget::Budget::unlimited(), || {
        annulus_polar(DVec2::ZERO, r_in, r_out, dp)
    })?;
    let (u, w) = axis.any_orthonormal_pair();
    let nz = slices as usize;
    let dz = length / nz as f64;
    let mut out = ParticleSet::<D3>::new();
    for m in 0..nz {
        let c = base + axis * ((m as f64 + 0.5) * dz);
        let positions = ring.positions().iter().map(|p| c + u * p.x + w * p.y);
        let mut slice = ParticleSet::<D3>::from_parts(
            positions.collect(),
            ring.volumes().iter().map(|v| v * dz).collect(),
        )?
        .with_spacing(dp);
        for name in ring.regions() {
            let members = ring.tagged(name)?;
            slice.tag_particles(name, &members)?;
        }
        out.extend(&slice)?;
    }
    Ok(out)
}

/// A 3D hollow sphere `r_in ≤ r ≤ r_out` (a ball if `r_in = 0`) in body-fitted concentric
/// spherical layers, the 3D counterpart of [`annulus_polar`]: the surfaces are smooth spheres
/// instead of the staircase a lattice cut leaves (compare [`hollow_sphere`]).
///
/// The shell is split into `n_r = max(1, round((r_out − r_in)/dp))` layers of thickness
/// `dr = (r_out − r_in)/n_r`. Layer `k` lies on the sphere of radius `r_k = r_in + (k + ½) dr`
/// and holds `n_k = max(1, round(4π r_k² / dp²))` points of a Fibonacci (golden-spiral)
/// lattice about the z axis — `z = r_k (1 − (2j + 1)/n_k)`, azimuth `j ψ + k ψ/2` with the
/// golden angle `ψ = π(3 − √5)` — whose points cover the sphere with near-equal areas; the
/// azimuth offset `k ψ/2` turns each layer against its neighbours so the layers do not align
/// radially. Every particle of layer `k` gets the exact volume of its share of the layer,
/// `V = 4π/3 ((r_k + dr/2)³ − (r_k − dr/2)³) / n_k`, so the volumes sum to
/// `4π/3 (r_out³ − r_in³)` to round-off. For a ball (`r_in = 0`) the innermost layer, the ball
/// of radius `dr`, is a central cluster of 4 particles on a regular tetrahedron of
/// circumradius `√(3/8) dr` (edge `dr`), each with a quarter of its volume.
///
/// The points are mirror-symmetric in `z` (the Fibonacci heights come in pairs `±z`), not in
/// `x` or `y`; reflect a copy ([`ParticleSet::positions`] mapped by `x → −x`) where a scene
/// needs two mirror-image bodies. The Fibonacci poles (slightly less regular than the rest)
/// are on the z axis: orient a scene so that its contact points are away from them.
/// Regions: `"outer"` (layer `n_r − 1`) and, if `r_in > 0`, `"inner"` (layer 0).
pub fn hollow_sphere_polar(
    centre: DVec3,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D3>, Error> {
    check_positive("dp", dp)?;
    check_radii(r_in, r_out)?;
    if !centre.is_finite() {
        return Err(Error::invalid("centre", centre, "finite"));
    }
    budget::reserve::<D3>(
        sphere_particle_estimate(r_in, r_out, dp),
        &format!("hollow_sphere_polar at dp = {dp:?}"),
    )?;
    let shell_volume = |r: f64, dr: f64| {
        let (a, b) = (r - 0.5 * dr, r + 0.5 * dr);
        4.0 / 3.0 * PI * (b * b * b - a * a * a)
    };
    let (dr, radii) = ring_layers(r_in, r_out, dp);
    let golden = PI * (3.0 - 5f64.sqrt());
    let mut positions = Vec::new();
    let mut volumes = Vec::new();
    let mut layer = Vec::new();
    for (k, &r) in radii.iter().enumerate() {
        if k == 0 && r_in == 0.0 {
            // Central cluster: regular tetrahedron of edge dr.
            let rc = (3.0f64 / 8.0).sqrt() * dr;
            let v = shell_volume(r, dr) / 4.0;
            for s in [
                [1.0, 1.0, 1.0],
                [1.0, -1.0, -1.0],
                [-1.0, 1.0, -1.0],
                [-1.0, -1.0, 1.0],
            ] {
                positions.push(centre + DVec3::from_array(s) * (rc / 3f64.sqrt()));
                volumes.push(v);
                layer.push(k);
            }
            continue;
        }
        let n = (4.0 * PI * r * r / (dp * dp)).round().max(1.0) as usize;
        let v = shell_volume(r, dr) / n as f64;
        let offset = 0.5 * golden * k as f64;
        for j in 0..n {
            let z = 1.0 - (2.0 * j as f64 + 1.0) / n as f64;
            let rho = (1.0 - z * z).max(0.0).sqrt();
            let (s, c) = (golden * j as f64 + offset).sin_cos();
            positions.push(centre + DVec3::new(rho * c, rho * s, z) * r);
            volumes.push(v);
            layer.push(k);
        }
    }
    let mut set = ParticleSet::from_parts(positions, volumes)?.with_spacing(dp);
    let last = radii.len() - 1;
    if r_in > 0.0 {
        set.tag_where("inner", |i, _| layer[i] == 0)?;
    }
    set.tag_where("outer", |i, _| layer[i] == last)?;
    Ok(set)
}

/// A 3D hollow sphere (ball if `r_in = 0`) filled on a lattice whose cell faces pass through the
/// centre, so the particles are symmetric under reflection in each coordinate plane through it.
/// `V = dp³`; the total volume approaches `4π/3 (r_out³ − r_in³)` to first order in `dp`. The
/// surfaces are staircases of lattice cells; [`hollow_sphere_polar`] gives smooth ones.
pub fn hollow_sphere(
    centre: DVec3,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D3>, Error> {
    let lattice = Lattice::<D3>::new(dp, centre)?;
    ParticleSet::fill(&lattice, &HollowSphere::new(centre, r_in, r_out)?)
}

/// A 2D ring (disc if `r_in = 0`) filled on a lattice whose cell faces pass through the centre
/// (symmetric particles); `V = dp²`. See [`annulus_polar`] for smooth circular surfaces.
pub fn annulus_lattice(
    centre: DVec2,
    r_in: f64,
    r_out: f64,
    dp: f64,
) -> Result<ParticleSet<D2>, Error> {
    let lattice = Lattice::<D2>::new(dp, centre)?;
    ParticleSet::fill(&lattice, &Annulus::new(centre, r_in, r_out)?)
}
