//! Checkpoint state of the UL solver (`Solver::save_state` / `restore_state`).

use super::*;

impl<D: Dim> UlSolver<D> {
    /// [`Solver::save_state`] of this solver (see there).
    pub(super) fn write_state(&self, out: &mut StateWriter) -> Result<(), Error> {
        let index: Vec<u64> = self.original_index.iter().map(|&o| u64::from(o)).collect();
        out.u64s("original_index", &index);
        out.vectors::<D>("positions", &self.positions);
        out.vectors::<D>("velocities", &self.velocities);
        out.f64s("densities", &self.densities);
        out.matrices::<D>("stress", &self.stress);
        out.vectors::<D>("accumulated", &self.accumulated);
        let rate_density: Vec<f64> = self.rates.iter().map(|r| r.density).collect();
        let rate_stress: Vec<D::Matrix> = self.rates.iter().map(|r| r.stress).collect();
        let rate_shear: Vec<D::Vector> = self.rates.iter().map(|r| r.shear).collect();
        out.f64s("rate_density", &rate_density);
        out.matrices::<D>("rate_stress", &rate_stress);
        out.vectors::<D>("rate_shear", &rate_shear);
        out.vectors::<D>("accelerations", &self.accelerations);
        out.f64s("pressures", &self.pressures);
        out.f64s(
            "scalars",
            &[
                self.time,
                self.max_speed,
                self.schedule.next(),
                self.first_isolation.unwrap_or(f64::NAN),
            ],
        );
        out.u64s(
            "counters",
            &[
                self.steps,
                self.acoustic_steps,
                self.rebuilds,
                self.isolated as u64,
                self.isolated_max as u64,
                u64::from(self.first_isolation.is_some()),
                self.pair_visits,
            ],
        );
        save_probes(out, &self.probes);
        // The energy budget's accumulated works, the momentum balance and the contact series.
        let w = &self.work;
        out.f64s(
            "budget",
            &[
                w.riemann,
                w.artificial,
                w.contact,
                w.shear,
                w.loads,
                w.density_jump,
                self.initial_total,
            ],
        );
        out.vectors::<D>(
            "momentum_balance",
            &[self.initial_momentum, self.constraint_impulse],
        );
        save_series(out, &self.series);
        self.tools.save(out);
        // Contact friction, only with it (a frictionless checkpoint is unchanged).
        if let Some(f) = &self.contact_friction {
            f.save(out);
        }
        // The plastic history, only for a plastic body (an elastic checkpoint is unchanged).
        if !self.plastic.is_empty() {
            let column = |f: fn(&PlasticParticle) -> f64| -> Vec<f64> {
                self.plastic.iter().map(f).collect()
            };
            out.f64s(
                "plastic_strain",
                &column(|p| p.state.equivalent_plastic_strain),
            );
            out.f64s("temperature_rise", &column(|p| p.state.temperature_rise));
            out.f64s("plastic_dissipation", &column(|p| p.dissipated));
        }
        Ok(())
    }

    /// [`Solver::restore_state`] of this solver (see there).
    pub(super) fn read_state(&mut self, input: &mut StateReader<'_>) -> Result<(), Error> {
        let n = self.len();
        let saved = input.u64s("original_index", Some(n))?;
        let mut seen = vec![false; n];
        for &o in &saved {
            match seen.get_mut(o as usize) {
                Some(s) if !*s => *s = true,
                _ => {
                    return Err(Error::Checkpoint(format!(
                        "original_index is not a permutation of 0..{n} (entry {o})"
                    )))
                }
            }
        }
        let inv = self.inverse_index();
        let perm: Vec<u32> = saved.iter().map(|&o| inv[o as usize]).collect();
        self.permute(&perm);
        let n = Some(n);
        self.positions = input.vectors::<D>("positions", n)?;
        self.velocities = input.vectors::<D>("velocities", n)?;
        self.densities = input.f64s("densities", n)?;
        self.stress = input.matrices::<D>("stress", Some(self.stress.len()))?;
        self.accumulated = input.vectors::<D>("accumulated", Some(self.accumulated.len()))?;
        let rate_density = input.f64s("rate_density", n)?;
        let rate_stress = input.matrices::<D>("rate_stress", n)?;
        let rate_shear = input.vectors::<D>("rate_shear", n)?;
        for (k, r) in self.rates.iter_mut().enumerate() {
            (r.density, r.stress, r.shear) = (rate_density[k], rate_stress[k], rate_shear[k]);
        }
        self.accelerations = input.vectors::<D>("accelerations", n)?;
        self.pressures = input.f64s("pressures", n)?;
        let [time, max_speed, next_probe, first_isolation] = input.scalars::<4>("scalars")?;
        (self.time, self.max_speed) = (time, max_speed);
        self.schedule.set_next(next_probe);
        let c = input.u64s("counters", Some(7))?;
        self.pair_visits = c[6];
        (self.steps, self.acoustic_steps, self.rebuilds) = (c[0], c[1], c[2]);
        (self.isolated, self.isolated_max) = (c[3] as usize, c[4] as usize);
        self.first_isolation = (c[5] != 0).then_some(first_isolation);
        restore_probes(input, &mut self.probes)?;
        let [riemann, artificial, contact, shear, loads, density_jump, initial_total] =
            input.scalars::<7>("budget")?;
        self.work = AccumulatedWork {
            riemann,
            artificial,
            contact,
            shear,
            loads,
            density_jump,
        };
        self.initial_total = initial_total;
        let m = input.vectors::<D>("momentum_balance", Some(2))?;
        (self.initial_momentum, self.constraint_impulse) = (m[0], m[1]);
        restore_series(input, &mut self.series)?;
        self.tools.restore(input)?;
        if let Some(f) = &mut self.contact_friction {
            f.restore(input)?;
        }
        if !self.plastic.is_empty() {
            let eps = input.f64s("plastic_strain", n)?;
            let temperature = input.f64s("temperature_rise", n)?;
            let dissipated = input.f64s("plastic_dissipation", n)?;
            for (k, p) in self.plastic.iter_mut().enumerate() {
                p.state.equivalent_plastic_strain = eps[k];
                p.state.temperature_rise = temperature[k];
                p.dissipated = dissipated[k];
            }
        }
        self.check_finite()
    }
}
