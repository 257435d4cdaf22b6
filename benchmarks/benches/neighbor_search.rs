//! Neighbour-list build for ~1e5 particles in 3D: cell-linked list vs kiddo kd-tree, on 1 and 2
//! threads. Run with `cargo bench -p sph-benchmarks --bench neighbor_search`; then
//! `cargo run --release -p sph-benchmarks --bin perf-report` writes `docs/performance.md`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sph_benchmarks::{jittered_lattice_3d, thread_pool, NEIGHBOR_BENCH};
use sph_core::neighbor::{neighbor_list_cells, neighbor_list_kdtree};
use sph_core::{CellGrid, D3};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let spec = NEIGHBOR_BENCH;
    let (positions, dp) = jittered_lattice_3d(spec.per_axis, spec.jitter);
    let cutoff = 2.0 * spec.h_over_dp * dp;
    let mut group = c.benchmark_group(spec.group);
    group.sample_size(20);
    group.warm_up_time(std::time::Duration::from_secs(2));
    group.measurement_time(std::time::Duration::from_secs(6));
    group.throughput(Throughput::Elements(positions.len() as u64));
    for threads in [1usize, 2] {
        let pool = thread_pool(threads);
        let label = format!("{threads}-thread");
        group.bench_with_input(BenchmarkId::new("cell-list", &label), &threads, |b, _| {
            b.iter(|| {
                pool.install(|| {
                    let grid = CellGrid::<D3>::build(&positions, cutoff).unwrap();
                    black_box(grid.neighbor_list(&positions, cutoff).unwrap())
                })
            })
        });
        group.bench_with_input(
            BenchmarkId::new("cell-list-sorted", &label),
            &threads,
            |b, _| {
                b.iter(|| {
                    pool.install(|| {
                        black_box(neighbor_list_cells::<D3>(&positions, cutoff).unwrap())
                    })
                })
            },
        );
        group.bench_with_input(BenchmarkId::new("kd-tree", &label), &threads, |b, _| {
            b.iter(|| {
                pool.install(|| black_box(neighbor_list_kdtree::<D3>(&positions, cutoff).unwrap()))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
