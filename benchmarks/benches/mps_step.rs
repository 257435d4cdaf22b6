//! Cost of one step of the Hamiltonian MPS model beside TL-HF on the same particles: the MPS
//! paper's cantilever plate (free length 0.2, H = 0.02, 0.04 held in a 3-layer base; SVK,
//! K = 3.25 MPa, μ = 0.715 MPa, ρ = 1000) at H/dp = 5, 10, 20, first-mode initial velocity,
//! 1 and 2 threads. `cargo bench -p sph-benchmarks --bench mps_step`, then `perf-report`.
//! (The time per unit of simulated time also depends on Δt: MPS uses C l0/c0 with C = 0.1,
//! TL-HF 0.6 h/(c0 + |v|).)

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::DVec2;
use sph_benchmarks::{thread_pool, MPS_BENCH_GROUP, MPS_BENCH_RESOLUTIONS};
use sph_cases::cases::oscillating_plate_2d::{mode_shape, plate_particles};
use sph_core::Body;
use sph_core::{Constraint, Constraints, Solver, D2};
use sph_materials::{ElasticConstants, MaterialKind};
use sph_mps::{MpsParams, MpsSolver};
use sph_tl::{Shear, TlParams, TlSolver};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group(MPS_BENCH_GROUP);
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
    let constants = ElasticConstants::from_bulk_shear(3.25e6, 7.15e5, 1000.0).unwrap();
    for res in MPS_BENCH_RESOLUTIONS {
        let (set, dp) = plate_particles(0.2, 0.02, res, 0.04, 3).unwrap();
        let base = set.tagged("base").unwrap();
        let fl = mode_shape(0.2, 0.2);
        let velocities: Vec<DVec2> = set
            .positions()
            .iter()
            .map(|x| {
                let v = if x.x > 0.0 {
                    0.01 * constants.sound_speed * mode_shape(x.x, 0.2) / fl
                } else {
                    0.0
                };
                DVec2::new(0.0, v)
            })
            .collect();
        for threads in [1usize, 2] {
            let pool = thread_pool(threads);
            let fixed = || {
                let mut cons = Constraints::new();
                cons.push(
                    Constraint::Fixed {
                        particles: base.clone(),
                    },
                    set.len(),
                )
                .unwrap();
                cons
            };
            let mut mps = pool.install(|| {
                let body = Body::<D2> {
                    positions: set.positions().to_vec(),
                    volumes: set.volumes().to_vec(),
                    dp,
                    velocities: velocities.clone(),
                    densities: Vec::new(),
                };
                let m = MaterialKind::SaintVenantKirchhoff.build(constants).unwrap();
                MpsSolver::new(body, m, MpsParams::default())
                    .unwrap()
                    .with_constraints(fixed())
            });
            let mut tl = pool.install(|| {
                let body = Body::<D2> {
                    positions: set.positions().to_vec(),
                    volumes: set.volumes().to_vec(),
                    dp,
                    velocities: velocities.clone(),
                    densities: Vec::new(),
                };
                let m = MaterialKind::SaintVenantKirchhoff.build(constants).unwrap();
                TlSolver::new(body, m, Shear::hourglass_free(), TlParams::default())
                    .unwrap()
                    .with_constraints(fixed())
            });
            group.throughput(Throughput::Elements(set.len() as u64));
            group.bench_function(
                BenchmarkId::new(format!("mps/{threads}-thread"), res),
                |b| b.iter(|| pool.install(|| mps.step(f64::INFINITY).unwrap())),
            );
            group.bench_function(
                BenchmarkId::new(format!("tl-hf/{threads}-thread"), res),
                |b| b.iter(|| pool.install(|| tl.step(f64::INFINITY).unwrap())),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
