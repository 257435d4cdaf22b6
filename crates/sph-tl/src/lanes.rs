//! The pair loops of a 3D TL step with stored reference data, the HF acceleration (eq 29),
//! the stress divergence (eq 20) and the deformation rate (eq 22), with the three components
//! of a vector in one AVX register (the fourth lane zero).
//!
//! LLVM compiles glam's `DVec3`/`DMat3` arithmetic of these loops into two-lane SSE plus scalar
//! operations with shuffles between them, about 40 instructions per pair for the HF
//! acceleration. Here a vector, or a column of a matrix, is one register.
//!
//! **The same bits as the generic loops.** Every lane does the operations of the glam code in
//! the same order (`(P_i + P_j) g` as `((m₀ g_x) + (m₁ g_y)) + (m₂ g_z)`, columns first), with
//! separate multiplies and adds (LLVM never contracts them into fused multiply-adds on its
//! own). The fourth lane is loaded as zero (a masked load, which never reads past the third
//! component) and dropped. Tested against the generic loops bit for bit.
//!
//! Used when the loops run their AVX2 copy ([`sph_core::wide::enabled`]); the generic loops
//! otherwise, and for 2D, recomputed pair data and Ganzenmüller's penalty.

use glam::{DMat3, DVec3};
use sph_core::parallel::gather;
use sph_core::{NeighborList, NeighbourValues};
use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_maskload_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_set_epi64x,
    _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd,
};

/// Whether the loops of this module run: the particle loops run their AVX2 copy.
#[inline]
pub(crate) fn available() -> bool {
    sph_core::wide::enabled()
}

/// `[v.x, v.y, v.z, 0]`: a masked load, which reads the three components only.
///
/// # Safety
/// `v` points at three readable `f64`.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn load3(v: *const f64) -> __m256d {
    // SAFETY: the mask selects lanes 0–2, which the caller guarantees readable.
    unsafe { _mm256_maskload_pd(v, _mm256_set_epi64x(0, -1, -1, -1)) }
}

/// The lanes 0–2 of `r`.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn store3(r: __m256d) -> DVec3 {
    let mut out = [0.0; 4];
    // SAFETY: `out` holds four `f64`.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), r) };
    DVec3::new(out[0], out[1], out[2])
}

/// The three columns of `m`.
///
/// # Safety
/// None beyond the reference's validity (a `DMat3` is nine contiguous `f64`, column-major).
#[inline]
#[target_feature(enable = "avx2,fma")]
fn columns(m: &DMat3) -> [__m256d; 3] {
    let p = m as *const DMat3 as *const f64;
    // SAFETY: `DMat3` is `repr(C)` of three `DVec3`, each three `f64`.
    unsafe { [load3(p), load3(p.add(3)), load3(p.add(6))] }
}

/// `v` as a register.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn vector(v: &DVec3) -> __m256d {
    // SAFETY: `DVec3` is `repr(C)` of three `f64`.
    unsafe { load3(v as *const DVec3 as *const f64) }
}

/// `(A + B) g` for the columns of `A` and `B`, as glam computes `(a + b) * g`: the sum column
/// by column, then the x column times `g_x`, plus the y column times `g_y`, plus the z column
/// times `g_z` (`DMat3::mul_vec3`).
#[inline]
#[target_feature(enable = "avx2,fma")]
fn pair_sum_times(a: [__m256d; 3], b: [__m256d; 3], g: &DVec3) -> __m256d {
    let mut m = _mm256_mul_pd(_mm256_add_pd(a[0], b[0]), _mm256_set1_pd(g.x));
    m = _mm256_add_pd(
        m,
        _mm256_mul_pd(_mm256_add_pd(a[1], b[1]), _mm256_set1_pd(g.y)),
    );
    _mm256_add_pd(
        m,
        _mm256_mul_pd(_mm256_add_pd(a[2], b[2]), _mm256_set1_pd(g.z)),
    )
}

/// The two sums of [`crate::hourglass_free::acceleration`] for particle `i`:
/// `Σ_j (P_i + P_j) g_ij` and `Σ_j (x_i − x_j) (J_i^(−2/3) + J_j^(−2/3)) s_ij` over the row's
/// slots (`gradient`, `scalar`, `neighbours`).
///
/// # Safety
/// The neighbour indices are indices of the list that made the three views.
#[inline]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn hf_row(
    gradient: &[DVec3],
    scalar: &[f64],
    neighbours: &[u32],
    (p_j, x_j, iso_j): (
        NeighbourValues<'_, DMat3>,
        NeighbourValues<'_, DVec3>,
        NeighbourValues<'_, f64>,
    ),
    p_i: &DMat3,
    x_i: &DVec3,
    iso_i: f64,
) -> (DVec3, DVec3) {
    let pi = columns(p_i);
    let xi = vector(x_i);
    let mut div = _mm256_setzero_pd();
    let mut shear = _mm256_setzero_pd();
    for ((g, &s), &j) in gradient.iter().zip(scalar).zip(neighbours) {
        let j = j as usize;
        // SAFETY: `j` is an index of the list that made the views (the caller's contract).
        let (p, x, iso) = unsafe { (p_j.get(j), x_j.get(j), iso_j.at(j)) };
        div = _mm256_add_pd(div, pair_sum_times(pi, columns(p), g));
        let w = (iso_i + iso) * s;
        shear = _mm256_add_pd(
            shear,
            _mm256_mul_pd(_mm256_sub_pd(xi, vector(x)), _mm256_set1_pd(w)),
        );
    }
    (store3(div), store3(shear))
}

/// [`crate::hourglass_free::acceleration`] in 3D with stored pair data (`gradient`,
/// `scalar`: one per slot of `list`), the same bits.
///
/// # Panics
/// If the pair data do not have one entry per slot of `list`, or a per-particle slice is
/// shorter than the list's indices need.
#[allow(clippy::too_many_arguments)]
pub(crate) fn hf_acceleration(
    list: &NeighborList,
    gradient: &[DVec3],
    scalar: &[f64],
    remaining: &[DMat3],
    positions: &[DVec3],
    isochoric: &[f64],
    inv_density: f64,
    zeta_g_over_rho: f64,
    acc: &mut [DVec3],
) {
    // What the loops need is the CPU's (another thread may switch the AVX2 copy off meanwhile;
    // the results are the same bits on either copy).
    assert!(
        sph_core::wide::cpu_has_avx2_fma(),
        "the AVX loops need a CPU with AVX2 and FMA"
    );
    assert!(gradient.len() == list.num_pairs() && scalar.len() == list.num_pairs());
    let views = (
        list.values(remaining),
        list.values(positions),
        list.values(isochoric),
    );
    gather(
        acc,
        #[inline(always)]
        |i, a| {
            let range = list.range(i);
            // SAFETY: the CPU has AVX2 and FMA (asserted above); the row's indices are
            // indices of `list`, which made the views.
            let (div, shear) = unsafe {
                hf_row(
                    &gradient[range.clone()],
                    &scalar[range],
                    list.neighbors(i),
                    views,
                    &remaining[i],
                    &positions[i],
                    isochoric[i],
                )
            };
            *a = crate::hourglass_free::acceleration_from_sums::<sph_core::dim::D3>(
                div,
                shear,
                inv_density,
                zeta_g_over_rho,
            );
        },
    );
}

/// `Σ_j (S_i + S_j) g_ij` of [`crate::original::stress_divergence`] over particle `i`'s
/// slots.
///
/// # Safety
/// The neighbour indices are indices of the list that made the view.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn divergence_row(
    gradient: &[DVec3],
    neighbours: &[u32],
    s_j: NeighbourValues<'_, DMat3>,
    s_i: &DMat3,
) -> DVec3 {
    let si = columns(s_i);
    let mut sum = _mm256_setzero_pd();
    for (g, &j) in gradient.iter().zip(neighbours) {
        // SAFETY: `j` is an index of the list that made the view (the caller's contract).
        let sj = columns(unsafe { s_j.get(j as usize) });
        sum = _mm256_add_pd(sum, pair_sum_times(si, sj, g));
    }
    store3(sum)
}

/// [`crate::original::stress_divergence`] in 3D with stored gradients (one per slot of
/// `list`), the same bits.
///
/// # Panics
/// As [`hf_acceleration`].
pub(crate) fn stress_divergence(
    list: &NeighborList,
    gradient: &[DVec3],
    stress: &[DMat3],
    inv_density: f64,
    acc: &mut [DVec3],
) {
    // What the loops need is the CPU's (another thread may switch the AVX2 copy off meanwhile;
    // the results are the same bits on either copy).
    assert!(
        sph_core::wide::cpu_has_avx2_fma(),
        "the AVX loops need a CPU with AVX2 and FMA"
    );
    assert_eq!(gradient.len(), list.num_pairs());
    let s_j = list.values(stress);
    gather(
        acc,
        #[inline(always)]
        |i, a| {
            let range = list.range(i);
            // SAFETY: as in `hf_acceleration`.
            let sum =
                unsafe { divergence_row(&gradient[range], list.neighbors(i), s_j, &stress[i]) };
            *a = sum * inv_density;
        },
    );
}

/// `Σ_j (v_j − v_i) ⊗ g_ij` of [`crate::original::deformation_rate`] over particle `i`'s
/// slots, as its three columns `Σ_j (v_j − v_i) g_ij,k`.
///
/// # Safety
/// The neighbour indices are indices of the list that made the view.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn rate_row(
    gradient: &[DVec3],
    neighbours: &[u32],
    v_j: NeighbourValues<'_, DVec3>,
    v_i: &DVec3,
) -> DMat3 {
    let vi = vector(v_i);
    let mut c = [_mm256_setzero_pd(); 3];
    for (g, &j) in gradient.iter().zip(neighbours) {
        // SAFETY: `j` is an index of the list that made the view (the caller's contract).
        let d = _mm256_sub_pd(vector(unsafe { v_j.get(j as usize) }), vi);
        // outer(d, g) = [d g_x, d g_y, d g_z], added column by column.
        c[0] = _mm256_add_pd(c[0], _mm256_mul_pd(d, _mm256_set1_pd(g.x)));
        c[1] = _mm256_add_pd(c[1], _mm256_mul_pd(d, _mm256_set1_pd(g.y)));
        c[2] = _mm256_add_pd(c[2], _mm256_mul_pd(d, _mm256_set1_pd(g.z)));
    }
    DMat3::from_cols(store3(c[0]), store3(c[1]), store3(c[2]))
}

/// [`crate::original::deformation_rate`] in 3D with stored gradients (one per slot of
/// `list`), the same bits.
///
/// # Panics
/// As [`hf_acceleration`].
pub(crate) fn deformation_rate(
    list: &NeighborList,
    gradient: &[DVec3],
    correction: &[DMat3],
    velocities: &[DVec3],
    f_dot: &mut [DMat3],
) {
    // What the loops need is the CPU's (another thread may switch the AVX2 copy off meanwhile;
    // the results are the same bits on either copy).
    assert!(
        sph_core::wide::cpu_has_avx2_fma(),
        "the AVX loops need a CPU with AVX2 and FMA"
    );
    assert_eq!(gradient.len(), list.num_pairs());
    let v_j = list.values(velocities);
    gather(
        f_dot,
        #[inline(always)]
        |i, fd| {
            let range = list.range(i);
            // SAFETY: as in `hf_acceleration`.
            let sum = unsafe { rate_row(&gradient[range], list.neighbors(i), v_j, &velocities[i]) };
            *fd = sum * correction[i];
        },
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference_pairs::{PairScalar, PairStorage, PairView, ReferencePairs};
    use sph_core::dim::D3;
    use sph_core::neighbor::neighbor_list_cells;
    use sph_core::{Kernel, WendlandC2};

    /// Reference positions, volumes, per-particle matrices, positions and scalars.
    type Scene = (Vec<DVec3>, Vec<f64>, Vec<DMat3>, Vec<DVec3>, Vec<f64>);

    /// A jittered 7×7×7 block with arbitrary per-particle fields (a pseudo-random sequence).
    fn scene() -> Scene {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let dp = 0.1;
        let mut x0 = Vec::new();
        for k in 0..7 {
            for j in 0..7 {
                for i in 0..7 {
                    let jitter = DVec3::new(next(), next(), next()) * 0.2 * dp;
                    x0.push(DVec3::new(i as f64, j as f64, k as f64) * dp + jitter);
                }
            }
        }
        let n = x0.len();
        let volumes = (0..n)
            .map(|_| dp * dp * dp * (1.0 + 0.1 * next()))
            .collect();
        let matrices = (0..n)
            .map(|_| DMat3::from_cols_array(&[0.0; 9].map(|_: f64| 1e5 * next())))
            .collect();
        let x = x0
            .iter()
            .map(|&p| p * 1.1 + DVec3::new(next(), next(), next()) * 0.01)
            .collect();
        let scalars = (0..n).map(|_| 1.0 + 0.3 * next()).collect();
        (x0, volumes, matrices, x, scalars)
    }

    #[test]
    fn both_loops_are_the_generic_loops_bit_for_bit() {
        if !available() {
            return;
        }
        let (x0, volumes, matrices, x, iso) = scene();
        let kernel = WendlandC2::<D3>::from_spacing(0.1, 1.3).unwrap();
        let list = neighbor_list_cells::<D3>(&x0, kernel.cutoff()).unwrap();
        let (pairs, bad) = ReferencePairs::<D3>::new(
            &list,
            &x0,
            &volumes,
            &kernel,
            PairScalar::Laplacian,
            PairStorage::Stored,
        );
        assert!(bad.is_none());
        let PairView::Stored(rows) = pairs.view(&list, &x0, &volumes, &kernel) else {
            panic!("stored");
        };
        let (g, s) = crate::reference_pairs::PairRows::<D3>::stored(&rows).unwrap();
        let n = x0.len();
        let bits = |v: &[DVec3]| -> Vec<u64> {
            v.iter()
                .flat_map(|a| a.to_array())
                .map(f64::to_bits)
                .collect()
        };
        let (mut fast, mut generic) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        hf_acceleration(&list, g, s, &matrices, &x, &iso, 0.37, 1.9, &mut fast);
        crate::hourglass_free::acceleration_generic::<D3>(
            rows,
            &matrices,
            &x,
            &iso,
            0.37,
            1.9,
            &mut generic,
        );
        assert!(generic.iter().all(|a| a.length() > 0.0));
        assert_eq!(bits(&fast), bits(&generic));

        let (mut fast, mut generic) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        stress_divergence(&list, g, &matrices, 0.37, &mut fast);
        crate::original::stress_divergence_generic::<D3>(rows, &matrices, 0.37, &mut generic);
        assert!(generic.iter().all(|a| a.length() > 0.0));
        assert_eq!(bits(&fast), bits(&generic));

        let mat_bits = |v: &[DMat3]| -> Vec<u64> {
            v.iter()
                .flat_map(|m| m.to_cols_array())
                .map(f64::to_bits)
                .collect()
        };
        let (mut fast, mut generic) = (vec![DMat3::ZERO; n], vec![DMat3::ZERO; n]);
        deformation_rate(&list, g, &matrices, &x, &mut fast);
        crate::original::deformation_rate_generic::<D3>(rows, &matrices, &x, &mut generic);
        assert!(generic.iter().all(|m| *m != DMat3::ZERO));
        assert_eq!(mat_bits(&fast), mat_bits(&generic));
    }
}
