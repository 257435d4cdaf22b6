//! Builds the neighbour list of a jittered 3D lattice with both searches and prints what it found
//! and how long it took: a quick, real end-to-end check of the core on a new machine.
//!
//! ```text
//! cargo run --release -p sph-benchmarks --bin neighbours -- [particles per axis, default 47]
//! ```

use sph_benchmarks::{jittered_lattice_3d, NEIGHBOR_BENCH};
use sph_core::neighbor::neighbor_list_kdtree;
use sph_core::{CellGrid, D3};
use std::time::Instant;

fn main() {
    let per_axis = match std::env::args().nth(1) {
        None => NEIGHBOR_BENCH.per_axis,
        Some(s) => match s.parse::<usize>() {
            Ok(n) if (2..=300).contains(&n) => n,
            _ => {
                eprintln!("error: particles per axis must be an integer in 2..=300, got {s:?}");
                std::process::exit(2);
            }
        },
    };
    let (positions, dp) = jittered_lattice_3d(per_axis, NEIGHBOR_BENCH.jitter);
    let cutoff = 2.0 * NEIGHBOR_BENCH.h_over_dp * dp;
    println!(
        "{} particles, dp = {dp:.4e}, cut-off = {cutoff:.4e}, {} threads",
        positions.len(),
        rayon::current_num_threads()
    );
    let t = Instant::now();
    let mut cells = CellGrid::<D3>::build(&positions, cutoff)
        .and_then(|g| g.neighbor_list(&positions, cutoff))
        .unwrap_or_else(|e| fail(e));
    let t_cells = t.elapsed().as_secs_f64();
    let t = Instant::now();
    cells.sort_rows();
    let t_sort = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let kd = neighbor_list_kdtree::<D3>(&positions, cutoff).unwrap_or_else(|e| fail(e));
    let t_kd = t.elapsed().as_secs_f64();
    println!(
        "cell list: {:>8.2} ms  ({:.3e} particles/s), {} pairs, neighbours per particle {}..{}",
        t_cells * 1e3,
        positions.len() as f64 / t_cells,
        cells.num_pairs(),
        cells.min_count(),
        cells.max_count()
    );
    println!("  + sorting the rows: {:>6.2} ms", t_sort * 1e3);
    println!(
        "kd-tree:   {:>8.2} ms  ({:.3e} particles/s), {} pairs",
        t_kd * 1e3,
        positions.len() as f64 / t_kd,
        kd.num_pairs()
    );
    if cells.offsets() != kd.offsets() || cells.indices() != kd.indices() {
        eprintln!("error: the two searches disagree");
        std::process::exit(1);
    }
    println!("both searches found identical neighbour lists");
}

fn fail(e: sph_core::Error) -> ! {
    eprintln!("error: {e}");
    std::process::exit(1)
}
