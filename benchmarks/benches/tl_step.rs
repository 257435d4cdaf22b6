//! Cost of one TL step on the bending column (TL paper §4.4, Table 3) for TL, TL-HF and TL-GM
//! at H/dp = 6, 12, 24, on 1 and 2 threads. Each iteration is one full position-Verlet step
//! (forces, deformation rate, integration, constraints); the column is built once per variant.
//! `cargo bench -p sph-benchmarks --bench tl_step`, then `perf-report`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::DVec3;
use sph_benchmarks::{thread_pool, TL_BENCH_GROUP, TL_BENCH_METHODS, TL_BENCH_RESOLUTIONS};
use sph_cases::cases::bending_column_3d::column_particles;
use sph_core::Body;
use sph_core::{Constraint, Constraints, Solver};
use sph_materials::{ElasticConstants, MaterialKind};
use sph_tl::{Shear, TlParams, TlSolver};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group(TL_BENCH_GROUP);
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(4));
    let constants = ElasticConstants::from_youngs(17e6, 0.45, 1100.0).unwrap();
    for res in TL_BENCH_RESOLUTIONS {
        let (set, dp) = column_particles(1.0, 6.0, res, 3).unwrap();
        let clamp = set.tagged("clamp").unwrap();
        let v0 = DVec3::new(3f64.sqrt() / 2.0, 0.5, 0.0) * 10.0;
        let velocities: Vec<DVec3> = set
            .positions()
            .iter()
            .map(|x| if x.z > 0.0 { v0 } else { DVec3::ZERO })
            .collect();
        for method in TL_BENCH_METHODS {
            let shear = match method {
                "tl" => Shear::Original,
                "tl-hf" => Shear::hourglass_free(),
                _ => Shear::ganzenmuller(),
            };
            for threads in [1usize, 2] {
                let pool = thread_pool(threads);
                let mut solver = pool.install(|| {
                    let body = Body::<sph_core::D3> {
                        positions: set.positions().to_vec(),
                        volumes: set.volumes().to_vec(),
                        dp,
                        velocities: velocities.clone(),
                        densities: Vec::new(),
                    };
                    let material = MaterialKind::NeoHookean.build(constants).unwrap();
                    let mut cons = Constraints::new();
                    cons.push(
                        Constraint::Fixed {
                            particles: clamp.clone(),
                        },
                        set.len(),
                    )
                    .unwrap();
                    TlSolver::new(body, material, shear, TlParams::default())
                        .unwrap()
                        .with_constraints(cons)
                });
                group.throughput(Throughput::Elements(solver.len() as u64));
                let id = BenchmarkId::new(format!("{method}/{threads}-thread"), res);
                group.bench_function(id, |b| {
                    b.iter(|| pool.install(|| solver.step(f64::INFINITY).unwrap()))
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
