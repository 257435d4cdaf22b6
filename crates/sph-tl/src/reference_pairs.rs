//! The per-pair data of the reference configuration that the TL force passes read: the
//! volume-weighted kernel gradient `V_j ∇⁰_i W_ij` (eq 20 and 22) and the variant's pair
//! scalar (HF: [`laplacian_weight`], eq 27; GM: [`penalty_weight`]).
//!
//! They never change, so they can be computed once and stored, or recomputed from the reference
//! positions at every pass ([`PairStorage`]). Both read the same formula
//! ([`sph_core::pairs::pair_kernel`], then the same products), so a run gives the same bits
//! either way. Stored, a pair costs 24 B (2D: 16 B) for the gradient plus 8 B for the scalar on
//! top of its 4-byte neighbour index, about 2 KiB per particle in a 3D body at `h = 1.15 dp`
//! (≈ 56 neighbours); recomputed, only the index stays, at the price of a square root, a few
//! divisions and a kernel evaluation per pair and pass: measured on the 107,484-particle
//! bending column (TL-HF, 2 threads), the step takes about 2.5× as long (docs/performance.md).

use serde::{Deserialize, Serialize};
use sph_core::pairs::{pair_kernel, PairKernel};
use sph_core::{Dim, NeighborList, WendlandC2};

/// How a TL solver holds the per-pair reference data (see the module documentation). Both
/// choices give the same results bit for bit; only speed and memory differ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PairStorage {
    /// Compute once, keep for the run (the default: the fastest step).
    #[default]
    Stored,
    /// Recompute from the reference positions at every force pass and keep only the neighbour
    /// indices: for bodies that would not fit otherwise (3D TL-HF: under 1 KiB per particle,
    /// about 2.5× the run time; docs/performance.md).
    Recomputed,
}

impl PairStorage {
    /// The name a case or scene key spells.
    pub fn name(self) -> &'static str {
        match self {
            PairStorage::Stored => "stored",
            PairStorage::Recomputed => "recomputed",
        }
    }

    /// The storage a key names (`stored`, `recomputed`).
    pub fn from_name(name: &str) -> Option<Self> {
        [PairStorage::Stored, PairStorage::Recomputed]
            .into_iter()
            .find(|s| s.name() == name)
    }
}

/// The pair scalar a variant reads beside the gradient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PairScalar {
    /// Plain TL-SPH: none.
    None,
    /// TL-SPH-HF: [`laplacian_weight`].
    Laplacian,
    /// TL-SPH with Ganzenmüller's penalty: [`penalty_weight`].
    Penalty,
}

impl PairScalar {
    #[inline(always)]
    fn of<D: Dim>(self, p: &PairKernel<D>, kernel: &WendlandC2<D>, volume_j: f64) -> f64 {
        match self {
            PairScalar::None => 0.0,
            PairScalar::Laplacian => laplacian_weight(p, volume_j),
            PairScalar::Penalty => penalty_weight(p, kernel, volume_j),
        }
    }
}

/// `V_j ∇⁰_i W_ij` of one pair (TL paper eq 20, 22).
#[inline(always)]
pub fn gradient_weight<D: Dim>(p: &PairKernel<D>, volume_j: f64) -> D::Vector {
    p.grad() * volume_j
}

/// `V_j W′(r⁰_ij)/r⁰_ij`: the weight of `x_ij` in the HF Laplacian of position (TL paper
/// eq 27).
#[inline(always)]
pub fn laplacian_weight<D: Dim>(p: &PairKernel<D>, volume_j: f64) -> f64 {
    volume_j * p.dw / p.r
}

/// `V_j W(r⁰_ij)/|X_ij|²`: the pair weight of Ganzenmüller's hourglass penalty
/// ([`crate::ganzenmuller`]), `W` of `kernel` (the kernel of `p`).
#[inline(always)]
pub fn penalty_weight<D: Dim>(p: &PairKernel<D>, kernel: &WendlandC2<D>, volume_j: f64) -> f64 {
    volume_j * p.w(kernel) / (p.r * p.r)
}

/// The stored form: one gradient and (unless the variant has none) one scalar per list slot.
#[derive(Clone, Debug)]
struct Stored<D: Dim> {
    gradient: Vec<D::Vector>,
    scalar: Vec<f64>,
}

/// The reference pair data of one TL body, stored or recomputed (see [`PairStorage`]).
#[derive(Clone, Debug)]
pub(crate) struct ReferencePairs<D: Dim> {
    scalar: PairScalar,
    stored: Option<Stored<D>>,
}

impl<D: Dim> ReferencePairs<D> {
    /// Builds the data of `list` over the reference positions `reference`; computes and keeps
    /// them when `storage` stores in `D`. Returns the first list slot whose scalar is not
    /// finite (coincident reference positions), if any.
    pub(crate) fn new(
        list: &NeighborList,
        reference: &[D::Vector],
        volumes: &[f64],
        kernel: &WendlandC2<D>,
        scalar: PairScalar,
        storage: PairStorage,
    ) -> (Self, Option<usize>) {
        use rayon::prelude::*;
        let pair = |i: usize, j: u32| {
            let p = pair_kernel::<D, _>(reference[i] - reference[j as usize], kernel);
            (p, volumes[j as usize])
        };
        let stored = (storage == PairStorage::Stored).then(|| {
            let rows = (0..list.len()).into_par_iter();
            if scalar == PairScalar::None {
                let gradient = rows
                    .flat_map_iter(|i| {
                        list.neighbors(i).iter().map(move |&j| {
                            let (p, v) = pair(i, j);
                            gradient_weight(&p, v)
                        })
                    })
                    .collect();
                return Stored {
                    gradient,
                    scalar: Vec::new(),
                };
            }
            let (gradient, scalar) = rows
                .flat_map_iter(|i| {
                    list.neighbors(i).iter().map(move |&j| {
                        let (p, v) = pair(i, j);
                        (gradient_weight(&p, v), scalar.of(&p, kernel, v))
                    })
                })
                .unzip();
            Stored { gradient, scalar }
        });
        // Only coincident reference positions make r⁰ = 0 and the scalar non-finite.
        let bad = match (&stored, scalar) {
            (_, PairScalar::None) => None,
            (Some(s), _) => s.scalar.iter().position(|v| !v.is_finite()),
            (None, _) => (0..list.len()).find_map(|i| {
                list.range(i).zip(list.neighbors(i)).find_map(|(k, &j)| {
                    let (p, v) = pair(i, j);
                    (!scalar.of(&p, kernel, v).is_finite()).then_some(k)
                })
            }),
        };
        (Self { scalar, stored }, bad)
    }

    /// Restricts stored data to the list slots `slots` (in that order), for a rank's local
    /// list in a distributed run; recomputed data need nothing.
    pub(crate) fn pick_slots(&mut self, slots: &[usize]) {
        if let Some(s) = &mut self.stored {
            s.gradient = slots.iter().map(|&k| s.gradient[k]).collect();
            if !s.scalar.is_empty() {
                s.scalar = slots.iter().map(|&k| s.scalar[k]).collect();
            }
        }
    }

    /// Whether the data are held in memory.
    pub(crate) fn is_stored(&self) -> bool {
        self.stored.is_some()
    }

    /// The view the force passes read, with what recomputing needs (see [`with_pair_rows`]).
    pub(crate) fn view<'a>(
        &'a self,
        list: &'a NeighborList,
        reference: &'a [D::Vector],
        volumes: &'a [f64],
        kernel: &'a WendlandC2<D>,
    ) -> PairView<'a, D> {
        match &self.stored {
            Some(s) => PairView::Stored(StoredRows {
                list,
                gradient: &s.gradient,
                scalar: &s.scalar,
            }),
            None => PairView::Recomputed(RecomputedRows {
                list,
                reference,
                volumes,
                kernel,
                scalar: self.scalar,
            }),
        }
    }
}

/// The two views of [`ReferencePairs`]: each pass is compiled once per view, so neither pays
/// for the other's branch in its inner loop.
pub(crate) enum PairView<'a, D: Dim> {
    Stored(StoredRows<'a, D>),
    Recomputed(RecomputedRows<'a, D>),
}

/// Runs `$body` with `$rows` bound to the concrete view of `$view` (a [`PairView`]).
macro_rules! with_pair_rows {
    ($view:expr, |$rows:ident| $body:expr) => {
        match $view {
            $crate::reference_pairs::PairView::Stored($rows) => $body,
            $crate::reference_pairs::PairView::Recomputed($rows) => $body,
        }
    };
}
pub(crate) use with_pair_rows;

/// Row access to the reference pair data, stored ([`StoredRows`]) or recomputed
/// ([`RecomputedRows`]). Both visit a row's neighbours in list order with the same values.
/// The visits are folds: the accumulator travels by value (and the callers' closures capture
/// by `move`), so the inner loops keep their sums in registers.
pub trait PairRows<D: Dim>: Copy + Send + Sync {
    /// The neighbour list.
    fn list(&self) -> &NeighborList;

    /// Folds `f(acc, j, V_j ∇⁰_i W_ij)` over the neighbours `j` of particle `i`, in list order.
    fn fold_gradient<A>(&self, i: usize, init: A, f: impl FnMut(A, usize, D::Vector) -> A) -> A;

    /// Folds `f(acc, j, V_j ∇⁰_i W_ij, scalar)` over the neighbours `j` of particle `i`, in
    /// list order: the variant's pair scalar (HF and GM only; plain TL has none and reads
    /// [`PairRows::fold_gradient`]).
    fn fold<A>(&self, i: usize, init: A, f: impl FnMut(A, usize, D::Vector, f64) -> A) -> A;

    /// The stored gradients and pair scalars (empty for plain TL), one per list slot, when the
    /// data are stored ([`StoredRows`]); `None` when they are recomputed.
    fn stored(&self) -> Option<(&[D::Vector], &[f64])> {
        None
    }
}

/// Stored pair data (see [`PairStorage::Stored`]).
pub struct StoredRows<'a, D: Dim> {
    list: &'a NeighborList,
    gradient: &'a [D::Vector],
    scalar: &'a [f64],
}

impl<D: Dim> Clone for StoredRows<'_, D> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<D: Dim> Copy for StoredRows<'_, D> {}

impl<D: Dim> PairRows<D> for StoredRows<'_, D> {
    fn list(&self) -> &NeighborList {
        self.list
    }

    fn stored(&self) -> Option<(&[D::Vector], &[f64])> {
        Some((self.gradient, self.scalar))
    }

    #[inline(always)]
    fn fold_gradient<A>(
        &self,
        i: usize,
        init: A,
        mut f: impl FnMut(A, usize, D::Vector) -> A,
    ) -> A {
        let range = self.list.range(i);
        let mut acc = init;
        for (g, &j) in self.gradient[range].iter().zip(self.list.neighbors(i)) {
            acc = f(acc, j as usize, *g);
        }
        acc
    }

    #[inline(always)]
    fn fold<A>(&self, i: usize, init: A, mut f: impl FnMut(A, usize, D::Vector, f64) -> A) -> A {
        // Only the variants with a pair scalar (HF, GM) fold it; plain TL reads gradients.
        debug_assert!(!self.scalar.is_empty(), "no pair scalar stored");
        let range = self.list.range(i);
        let (g, s) = (&self.gradient[range.clone()], &self.scalar[range]);
        let mut acc = init;
        for ((g, s), &j) in g.iter().zip(s).zip(self.list.neighbors(i)) {
            acc = f(acc, j as usize, *g, *s);
        }
        acc
    }
}

/// Pair data recomputed from the reference positions (see [`PairStorage::Recomputed`]).
pub struct RecomputedRows<'a, D: Dim> {
    list: &'a NeighborList,
    reference: &'a [D::Vector],
    volumes: &'a [f64],
    kernel: &'a WendlandC2<D>,
    scalar: PairScalar,
}

impl<D: Dim> Clone for RecomputedRows<'_, D> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<D: Dim> Copy for RecomputedRows<'_, D> {}

impl<D: Dim> RecomputedRows<'_, D> {
    /// Folds row `i` with the pair data and `scalar(p, V_j)` (chosen outside the loop).
    #[inline(always)]
    fn visit<A>(
        &self,
        i: usize,
        init: A,
        scalar: impl Fn(&PairKernel<D>, f64) -> f64,
        mut f: impl FnMut(A, usize, D::Vector, f64) -> A,
    ) -> A {
        let xi = self.reference[i];
        let mut acc = init;
        for &j in self.list.neighbors(i) {
            let j = j as usize;
            let p = pair_kernel::<D, _>(xi - self.reference[j], self.kernel);
            let v = self.volumes[j];
            acc = f(acc, j, gradient_weight(&p, v), scalar(&p, v));
        }
        acc
    }
}

impl<D: Dim> PairRows<D> for RecomputedRows<'_, D> {
    fn list(&self) -> &NeighborList {
        self.list
    }

    #[inline(always)]
    fn fold_gradient<A>(
        &self,
        i: usize,
        init: A,
        mut f: impl FnMut(A, usize, D::Vector) -> A,
    ) -> A {
        self.visit(i, init, |_, _| 0.0, |acc, j, g, _| f(acc, j, g))
    }

    #[inline(always)]
    fn fold<A>(&self, i: usize, init: A, f: impl FnMut(A, usize, D::Vector, f64) -> A) -> A {
        match self.scalar {
            PairScalar::None => self.visit(i, init, |_, _| 0.0, f),
            PairScalar::Laplacian => self.visit(i, init, laplacian_weight, f),
            PairScalar::Penalty => self.visit(i, init, |p, v| penalty_weight(p, self.kernel, v), f),
        }
    }
}
