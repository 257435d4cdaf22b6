//! What the solver reports about its state: momentum, energies, the disorder indicator, the
//! Cauchy stress of the output fields, and the time series of the tools and named constraints.

use super::*;
use sph_core::conventions;

impl<D: Dim, M: Material<D>> TlSolver<D, M> {
    /// Empty series for the tools and named constraints, with a first row at the current time.
    pub(super) fn rebuild_series(&mut self) {
        let axes: &[&str] = if D::D == 2 {
            &["force_x", "force_y"]
        } else {
            &["force_x", "force_y", "force_z"]
        };
        let pos: &[&str] = if D::D == 2 {
            &["x", "y"]
        } else {
            &["x", "y", "z"]
        };
        let mut series = Vec::new();
        for (_, name) in self.constraints.named() {
            let mut columns = pos.to_vec();
            columns.extend_from_slice(axes);
            series.push(Series::new(name, &columns).with_description(conventions::GRIP_SERIES));
        }
        self.series = series;
        self.tools.reset_series(self.time);
        self.record_grip_series();
    }

    /// Appends one row to every series: tools' travel, mean reactions since the last row,
    /// the contact force on every body.
    pub(super) fn record_series(&mut self) {
        self.tools.record(self.time);
        self.record_grip_series();
        if let Some(c) = &mut self.contact {
            c.record(self.time, &self.masses);
        }
        if let Some(f) = &mut self.contact_friction {
            f.record(self.time);
        }
    }

    /// Appends one row to every grip's series: mean position, mean reaction since the last row.
    fn record_grip_series(&mut self) {
        let t = self.time;
        let mut row = Vec::with_capacity(8);
        let named: Vec<usize> = self.constraints.named().map(|(k, _)| k).collect();
        for (g, k) in named.into_iter().enumerate() {
            let particles = self.constraints.get(k).expect("named").particles();
            let mut mean = D::zero();
            for &i in particles {
                mean += self.positions[i as usize];
            }
            mean = mean / particles.len().max(1) as f64;
            row.clear();
            row.extend((0..D::D).map(|c| D::component(mean, c)));
            let f = self.grip_meters[g].take_mean();
            row.extend((0..D::D).map(|c| D::component(f, c)));
            self.series[g].push(t, &row);
        }
    }

    /// Total linear momentum `Σ m v` (over all ranks in a distributed run).
    pub fn linear_momentum(&self) -> D::Vector {
        self.domain
            .linear_momentum::<D>(&self.velocities, &self.masses)
    }

    /// Total angular momentum `Σ m x × v` about the origin (3-vector; only `z` in 2D; over all
    /// ranks in a distributed run).
    pub fn angular_momentum(&self) -> glam::DVec3 {
        self.domain
            .angular_momentum::<D>(&self.positions, &self.velocities, &self.masses)
    }

    /// Kinetic and strain energy (over all ranks in a distributed run); for a plastic body the
    /// strain energy is the Hencky energy of the elastic part (the plastic work is
    /// [`TlSolver::plastic_work`]).
    pub fn energy(&self) -> Energy {
        let kinetic =
            diagnostics::kinetic_energy::<D>(&self.velocities, &self.domain.counted(&self.masses));
        let strain = self
            .deformation
            .iter()
            .zip(&self.volumes)
            .enumerate()
            .filter(|(i, _)| self.domain.counts(*i))
            .map(|(i, (&f, &v))| match &self.plasticity {
                None => v * self.material.strain_energy_density(f).unwrap_or(f64::NAN),
                Some(p) => self.plastic_strain_energy(p, i),
            })
            .sum();
        let s = self.domain.sum_over_ranks(&[kinetic, strain]);
        Energy {
            kinetic: s[0],
            strain: s[1],
        }
    }

    /// The disorder indicator of docs/methods.md per particle.
    pub fn disorder(&self) -> Vec<f64> {
        disorder_indicator::<D>(
            &self.list,
            ReferenceWeights::Kernel(&self.kernel),
            &self.reference,
            &self.positions,
            &self.deformation,
        )
    }

    /// Cauchy stress (3×3, elastic part) of the law (every variant represents the material's
    /// law; see [`hourglass_free`] for the HF split).
    pub(super) fn cauchy_3d(&self, f: D::Matrix) -> glam::DMat3 {
        self.material.cauchy_stress_3d(f)
    }
}
