//! The HDF5 side of a run: fields as datasets, snapshots, and the compression check.

use super::*;

/// Converts a solver field to a dataset (vectors as `[n, 3]`, matrices as `[n, 3, 3]`, 2D
/// padded: z = 0 for vectors, the plane-strain `F_zz = 1` for matrices).
pub fn field_dataset<D: Dim>(name: &str, field: Field<D>) -> Dataset {
    match field {
        Field::Scalar(v) => Dataset::scalars(name, &v),
        Field::Vector(v) => {
            let a: Vec<[f64; 3]> = v.iter().map(|&x| D::to_vec3(x).to_array()).collect();
            Dataset::vectors(name, &a)
        }
        Field::Matrix(m) => {
            let a: Vec<[[f64; 3]; 3]> = m
                .iter()
                .map(|&x| {
                    let m3 = D::to_mat3(x, 1.0);
                    // Row-major rows for the file.
                    [
                        m3.row(0).to_array(),
                        m3.row(1).to_array(),
                        m3.row(2).to_array(),
                    ]
                })
                .collect();
            Dataset::matrices(name, &a)
        }
    }
}

/// Writes the solver's current state as the next snapshot: to this rank's own file with
/// per-rank output (its particles only), else to the results file (the whole body). Returns
/// the outcome and the datasets written (for the checkpoint), or `None` without output.
pub(super) fn write_snapshot<D: Dim>(
    own: Option<&mut crate::ranks::RankOutput>,
    writer: Option<&mut Box<dyn ResultWriter>>,
    solver: &dyn Solver<D>,
    fields: &[&str],
) -> Option<(Result<(), sph_output::OutputError>, Vec<Dataset>)> {
    let (t, step) = (solver.time(), solver.step_count());
    match (own, writer) {
        (Some(o), _) => {
            let sets = crate::ranks::owned_snapshot_datasets(solver, fields);
            Some((o.write(t, step, &sets), sets))
        }
        (None, Some(w)) => {
            let sets = snapshot_datasets(solver, fields);
            Some((w.write_snapshot(t, step, &sets), sets))
        }
        (None, None) => None,
    }
}

/// The datasets of a snapshot: the positions and the requested fields the solver offers.
pub(crate) fn snapshot_datasets<D: Dim>(solver: &dyn Solver<D>, fields: &[&str]) -> Vec<Dataset> {
    let pos: Vec<[f64; 3]> = solver
        .positions()
        .iter()
        .map(|&x| D::to_vec3(x).to_array())
        .collect();
    let ids: Vec<u64> = solver
        .particle_ids()
        .iter()
        .map(|&i| u64::from(i))
        .collect();
    let mut sets = vec![
        Dataset::vectors("position", &pos),
        Dataset::u64_scalars("id", &ids),
    ];
    for &name in fields {
        // `id` is the solver's, never a field of the same name.
        if name == "id" {
            continue;
        }
        if let Some(f) = solver.field(name) {
            sets.push(field_dataset::<D>(name, f));
        }
    }
    sets
}

/// Refuses a compression the run cannot honour: a deflate level outside 1..=9, or any
/// compression without a results file (nothing would be compressed).
pub(super) fn check_compression(options: &RunOptions) -> Result<(), DriverError> {
    match options.compression {
        Compression::None => Ok(()),
        Compression::Deflate(level) => {
            let allowed = if Compression::deflate(level).is_err() {
                "a deflate level, 1 (fastest) to 9 (smallest)"
            } else if options.output.is_none() {
                "no compression when no results file is written"
            } else {
                return Ok(());
            };
            Err(DriverError::InvalidValue {
                key: "compression".into(),
                value: format!("deflate {level}"),
                allowed: allowed.into(),
            })
        }
    }
}
