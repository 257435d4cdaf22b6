//! The work of one advection step: the neighbour rebuild (with cell-order reordering, the
//! kernel data and the correction matrix) and the acoustic sub-step of eq 23–25 with its
//! gathers (rates, forces) and element-wise passes; the module docs of [`super`] list the
//! order.

use super::*;
use sph_core::NeighbourValues;

/// The force gather's outputs (accelerations, the budget's parts: empty without the budget),
/// the pair data it reads, and whether it refreshes them first.
type ForceBuffers<'a, D> = (
    &'a mut [<D as Dim>::Vector],
    &'a mut [[<D as Dim>::Vector; 2]],
    &'a mut [PairKernel<D>],
    bool,
);

/// The neighbours' velocities, volumes and pressures the force gather reads.
type ForceNeighbours<'a, D> = (
    NeighbourValues<'a, <D as Dim>::Vector>,
    NeighbourValues<'a, f64>,
    NeighbourValues<'a, f64>,
);

impl<D: Dim> UlSolver<D> {
    /// Rebuild at the start of an advection step: cell list, reordering in cell order (applied
    /// to every per-particle field, constraints, loads and probes), neighbour list, frozen
    /// kernel data and the correction matrix `B` (eq 27).
    pub(super) fn rebuild(&mut self) -> Result<(), Error> {
        let cutoff = self.kernel.cutoff();
        let mut grid = CellGrid::<D>::build(&self.positions, cutoff)?;
        if self.params.reorder {
            let perm = grid.cell_order();
            if perm.iter().enumerate().any(|(k, &o)| k as u32 != o) {
                let perm = perm.to_vec();
                self.permute(&perm);
                grid = CellGrid::<D>::build(&self.positions, cutoff)?;
            }
        }
        self.list = grid.neighbor_list(&self.positions, cutoff)?;
        if let Some(contact) = &mut self.contact {
            self.list = contact.split(&self.list)?;
        }
        let n = self.len();
        if let Some(i) = (0..n).find(|&i| self.list.count(i) == 0) {
            if !self.params.allow_isolated {
                return Err(Error::LostNeighbours {
                    particle: self.original_index[i] as usize,
                    step: self.steps,
                    time: self.time,
                });
            }
            self.first_isolation.get_or_insert(self.time);
        }
        self.isolated = 0;
        for i in 0..n {
            if self.list.count(i) == 0 {
                self.isolated += 1;
                // A particle without neighbours has no shear force: ENOG's never-reset
                // accumulator (eq 20) would otherwise keep pushing a fragment for ever.
                if let Some(a) = self.accumulated.get_mut(i) {
                    *a = D::zero();
                }
            }
        }
        self.isolated_max = self.isolated_max.max(self.isolated);
        self.pairs.resize(self.list.num_pairs(), PairKernel::zero());
        self.halves = PairSymmetry::new(&self.list);
        self.refresh_pair_kernels();
        // On the team: a serial scan of the pairs was most of the rebuild's own time on the
        // stepping thread (the helper waiting).
        let pairs = &self.pairs;
        if let Some(k) = sph_core::parallel::first_index(pairs.len(), |k| pairs[k].r <= 0.0) {
            let i = self.list.offsets().partition_point(|&o| o <= k) - 1;
            return Err(Error::invalid(
                "positions",
                format!(
                    "particle {} coincides with a neighbour",
                    self.original_index[i]
                ),
                "distinct positions",
            ));
        }
        self.volumes
            .iter_mut()
            .zip(&self.masses)
            .zip(&self.densities)
            .for_each(|((v, &m), &rho)| *v = m / rho);
        let corr = correction_matrices::<D>(
            &self.list,
            &self.pairs,
            &self.volumes,
            self.params.correction_min_eigenvalue,
        )?;
        self.correction = corr.matrices;
        self.guarded = corr.guarded;
        self.rebuild_positions.clear();
        self.rebuild_positions.extend_from_slice(&self.positions);
        self.rebuilds += 1;
        Ok(())
    }

    /// `pairs` from the current positions: each unordered pair computed once when the list
    /// has its two halves (always, for a self list), bit for bit the plain fill otherwise.
    fn refresh_pair_kernels(&mut self) {
        let mut pairs = std::mem::take(&mut self.pairs);
        self.fill_pairs(&mut pairs);
        self.pairs = pairs;
    }

    /// The fill of [`Self::refresh_pair_kernels`] into `pairs` (a buffer of `self.list`).
    fn fill_pairs(&self, pairs: &mut [PairKernel<D>]) {
        let (x, list, kernel) = (&self.positions, &self.list, &self.kernel);
        match &self.halves {
            Some(halves) => halves.fill(x, list, kernel, pairs),
            None => fill_pair_kernels(x, x, list, kernel, pairs),
        }
    }

    /// Applies `perm[new] = old` to every per-particle field and relabels the scene.
    pub(super) fn permute(&mut self, perm: &[u32]) {
        fn p<T: Clone>(perm: &[u32], v: &mut Vec<T>) {
            if !v.is_empty() {
                *v = apply_permutation(perm, v);
            }
        }
        p(perm, &mut self.positions);
        p(perm, &mut self.velocities);
        p(perm, &mut self.densities);
        p(perm, &mut self.masses);
        p(perm, &mut self.plastic);
        p(perm, &mut self.gradients);
        p(perm, &mut self.stress);
        p(perm, &mut self.accumulated);
        p(perm, &mut self.rates);
        p(perm, &mut self.initial_positions);
        p(perm, &mut self.original_index);
        p(perm, &mut self.material);
        if let Some(c) = &mut self.contact {
            c.permute(perm);
        }
        p(perm, &mut self.free);
        p(perm, &mut self.accelerations);
        let inv = invert_permutation(perm);
        self.constraints.remap(&inv);
        self.loads.remap(&inv);
        for probe in &mut self.probes {
            probe.remap(&inv);
        }
    }

    /// Applies the velocity constraints and recomputes the rates and `|v|max` (after a state
    /// change).
    pub(super) fn refresh_rates(&mut self) {
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        self.update_pressures();
        self.max_speed = self.compute_rates(None);
    }

    /// Eq. (4) for every particle.
    fn update_pressures(&mut self) {
        let (mats, mat) = (&self.materials, &self.material);
        let (rho, m) = (&self.densities, &self.masses);
        gather2(
            &mut self.pressures,
            &mut self.current_volumes,
            #[inline(always)]
            |i, p, v| {
                let c = &mats[mat[i] as usize];
                *p = pressure(rho[i], c.density, c.sound_speed);
                *v = m[i] / rho[i];
            },
        );
    }

    /// Step 4 of the module docs: continuity (eq 11), the Jaumann rate of `τ` (eq 6–8, 14/26)
    /// and the ENOG rate (eq 19–20), in one gather over the neighbours; returns `|v|max` over
    /// the free particles. With `drift = Some((h, dt))` the same pass then applies eq 25 to
    /// each particle with its new rates (`x += h v`, `ρ += h dρ/dt`, `τ += h dτ/dt`) and eq 20
    /// (`A_s += dt dA_s/dt`): no particle's rates read another's `x`, `ρ`, `τ` or `A_s`, so
    /// this is the same as a gather followed by those updates.
    pub(super) fn compute_rates(&mut self, drift: Option<(f64, f64)>) -> f64 {
        let grad = self.tracks_stress;
        // ENOG's output stress and GNOG's penalty need the gradient exact for linear fields.
        let corrected = self.params.corrected_velocity_gradient
            || matches!(
                self.variant,
                Variant::NonNested { .. } | Variant::Generalized { .. }
            );
        match self.variant {
            Variant::NonNested { factor, form } => match (grad, form) {
                (true, LaplacianForm::Conservative) => {
                    self.rates_with_jump::<true, 1>(corrected, factor, drift)
                }
                (true, LaplacianForm::NonConservative) => {
                    self.rates_with_jump::<true, 2>(corrected, factor, drift)
                }
                (false, LaplacianForm::Conservative) => {
                    self.rates_with_jump::<false, 1>(corrected, factor, drift)
                }
                (false, LaplacianForm::NonConservative) => {
                    self.rates_with_jump::<false, 2>(corrected, factor, drift)
                }
            },
            _ => self.rates_with_jump::<true, 0>(corrected, 0.0, drift),
        }
    }

    /// [`Self::rates_loop`] with or without the continuity equation's pressure jump: the
    /// solid schemes have none, and then the loop neither reads `p_j` nor multiplies zeros
    /// (the same bits: the skipped terms are all `±0` added to `+0`).
    fn rates_with_jump<const GRAD: bool, const LAP: u8>(
        &mut self,
        corrected: bool,
        factor: f64,
        drift: Option<(f64, f64)>,
    ) -> f64 {
        if continuity_has_jump(self.params.riemann) {
            self.rates_loop::<GRAD, LAP, true>(corrected, factor, drift)
        } else {
            self.rates_loop::<GRAD, LAP, false>(corrected, factor, drift)
        }
    }

    /// The gather of [`Self::compute_rates`]; `GRAD`: velocity gradient and Jaumann rate;
    /// `LAP`: 0 none, 1 eq 19, 2 eq 18; `JUMP`: the scheme's pressure jump in eq 11.
    fn rates_loop<const GRAD: bool, const LAP: u8, const JUMP: bool>(
        &mut self,
        corrected: bool,
        factor: f64,
        drift: Option<(f64, f64)>,
    ) -> f64 {
        let n = self.len();
        // The energy budget's volumetric work of the pressure jump over the drift, per
        // particle at its start (summed in index order below).
        let jump_work = drift.is_some()
            && self.params.energy_budget
            && self.params.riemann == RiemannScheme::Paper;
        self.jump_work.resize(if jump_work { n } else { 0 }, 0.0);
        let list = &self.list;
        let pairs = &self.pairs;
        let (x_v, vol, p, b, m, free) = (
            &self.velocities,
            &self.current_volumes,
            &self.pressures,
            &self.correction,
            &self.masses,
            &self.free,
        );
        let (x_v_j, vol_j, p_j) = (list.values(x_v), list.values(vol), list.values(p));
        let (mats, mat, scheme) = (&self.materials, &self.material, self.params.riemann);
        let columns = (
            &mut self.rates[..],
            &mut self.positions[..],
            &mut self.densities[..],
            // Empty when ENOG's output-only stress is not integrated.
            &mut self.stress[..],
            // ENOG only.
            &mut self.accumulated[..],
            &mut self.jump_work[..],
            // Plastic bodies only.
            &mut self.plastic[..],
            // GNOG only.
            &mut self.gradients[..],
        );
        let plasticity = self.plasticity.as_ref();
        let max_norm2 = fold_columns(
            n,
            columns,
            #[inline(always)]
            |rows, (r, x, rho, tau, a_s, jw, hist, grads)| {
                let mut max_norm2 = 0.0;
                for (k, i) in rows.enumerate() {
                    let out = &mut r[k];
                    let (v_i, p_i, rho_i) = (x_v[i], p[i], rho[k]);
                    // Pairs join particles of one body, so of one material: particle i's.
                    let c = &mats[mat[i] as usize];
                    let (g, rho0, c0) = (c.shear_modulus, c.density, c.sound_speed);
                    let rho0_c0 = rho0 * c0;
                    let (mut drho, mut jump) = (0.0, 0.0);
                    let mut l = D::zero_matrix();
                    let mut lap = D::zero();
                    for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                        // SAFETY: `j` is an index of `list`, which made the three views.
                        let (v_j, x_v_j, p_j) = unsafe {
                            (
                                vol_j.at(j as usize),
                                x_v_j.at(j as usize),
                                p_j.at(j as usize),
                            )
                        };
                        let v_ij = v_i - x_v_j;
                        let u = D::dot(v_ij, pk.e);
                        drho += u * pk.dw * v_j;
                        if JUMP {
                            jump += continuity_jump(p_i, p_j, rho0_c0, scheme) * pk.dw * v_j;
                        }
                        if GRAD {
                            l += velocity_gradient_pair::<D>(v_ij, pk.e, pk.dw, v_j);
                        }
                        match LAP {
                            1 => {
                                lap +=
                                    conservative_laplacian_pair::<D>(v_ij, pk.e, pk.r, pk.dw, v_j)
                            }
                            2 => {
                                lap += non_conservative_laplacian_pair::<D>(v_ij, pk.r, pk.dw, v_j)
                            }
                            _ => {}
                        }
                    }
                    // Eq 11: ρ_i Σ [u_ij + (p_i − p_j)/(ρ0 c0)] W′ V_j, the jump part kept apart.
                    out.density = rho_i * (drho + jump);
                    out.density_jump = rho_i * jump;
                    if GRAD {
                        if corrected {
                            l = l * b[i];
                        }
                        out.stress = jaumann_rate::<D>(l, tau[k], g);
                        if !grads.is_empty() {
                            grads[k] = l;
                        }
                    }
                    if LAP != 0 {
                        out.shear = shear_acceleration_rate::<D>(lap, factor, g, rho_i);
                    }
                    if let Some((h, dt)) = drift {
                        if !jw.is_empty() {
                            jw[k] = m[i] * pressure(rho_i, rho0, c0) / (rho_i * rho_i)
                                * out.density_jump;
                        }
                        x[k] += v_i * h;
                        rho[k] += out.density * h;
                        if !tau.is_empty() {
                            tau[k] += out.stress * h;
                        }
                        if let Some(plasticity) = plasticity {
                            return_shear_stress::<D>(
                                plasticity,
                                &mut tau[k],
                                &mut hist[k],
                                m[i] / rho[k],
                                h,
                            );
                        }
                        if !a_s.is_empty() {
                            a_s[k] += out.shear * dt;
                        }
                    }
                    let v2 = if free[i] { D::norm_squared(v_i) } else { 0.0 };
                    max_norm2 = diagnostics::max_or_nan(max_norm2, v2);
                }
                max_norm2
            },
        );
        if let Some((h, _)) = drift.filter(|_| jump_work) {
            self.work.density_jump += h * self.jump_work.iter().sum::<f64>();
        }
        max_norm2
            .into_iter()
            .fold(0.0, diagnostics::max_or_nan)
            .sqrt()
    }

    /// Internal accelerations of the current state (pressure from `ρ`; the variant's shear
    /// term) into `self.accelerations`: step 2 of the module docs without loads or
    /// constraints. With `refresh`, the kernel data of the current positions first (the
    /// sub-step refresh), in the force gather's parallel region when the list has its halves
    /// ([`PairSymmetry::fill_then`]).
    fn compute_forces(&mut self, refresh: bool) {
        let mut out = std::mem::take(&mut self.accelerations);
        let mut parts = std::mem::take(&mut self.budget_parts);
        let mut pairs = std::mem::take(&mut self.pairs);
        let forces = (&mut out[..], &mut parts[..], &mut pairs[..], refresh);
        match self.variant {
            Variant::Original => self.forces_loop(NestedShear { tau: &self.stress }, forces),
            Variant::Artificial {
                epsilon,
                n,
                inv_w_dp,
            } => {
                let (tau, p, rho) = (&self.stress, &self.pressures, &self.densities);
                gather(
                    &mut self.artificial,
                    #[inline(always)]
                    |i, r| {
                        let sigma = tau[i] - D::identity() * p[i];
                        *r = artificial_stress::artificial_stress::<D>(sigma, rho[i], epsilon);
                    },
                );
                self.forces_loop(
                    ArtificialShear {
                        tau: &self.stress,
                        r: &self.artificial,
                        masses: &self.masses,
                        // With refreshed kernel data `W` is already the current one.
                        positions: (!self.params.refresh_kernel_data)
                            .then_some(&self.positions[..]),
                        kernel: &self.kernel,
                        inv_w_dp,
                        n,
                    },
                    forces,
                );
            }
            Variant::NonNested { .. } => self.forces_loop(
                AccumulatedShear {
                    a_s: &self.accumulated,
                },
                forces,
            ),
            Variant::Generalized { .. } => self.forces_loop(
                GeneralizedShear {
                    tau: &self.stress,
                    penalty: &self.accumulated,
                },
                forces,
            ),
        }
        self.pairs = pairs;
        self.budget_parts = parts;
        if let Some(contact) = &mut self.contact {
            contact.add_accelerations(
                &self.positions,
                &self.masses,
                &self.densities,
                &self.kernel,
                &mut out,
            );
        }
        self.accelerations = out;
    }

    /// The force gather: Riemann pressure (eq 12) plus the shear term `S`; with the energy
    /// budget also the dissipative part of the pressure and the artificial stress per particle.
    /// `parts` is empty when the budget is off. With `refresh`, `pairs` are first filled from
    /// the current positions: block by block in the gather's own tasks when the list has its
    /// halves (each block's force sums right after its pair data, one parallel region), else
    /// by a plain fill before the gather.
    fn forces_loop<S: ShearForce<D>>(
        &self,
        shear: S,
        (out, parts, pairs, refresh): ForceBuffers<'_, D>,
    ) {
        let list = &self.list;
        let neighbours = (
            list.values(&self.velocities),
            list.values(&self.current_volumes),
            list.values(&self.pressures),
        );
        let offsets = list.offsets();
        match (&self.halves, refresh) {
            (Some(halves), true) if parts.is_empty() => halves.fill_then(
                &self.positions,
                list,
                &self.kernel,
                pairs,
                (out,),
                #[inline(always)]
                |rows, block, (out,)| {
                    let base = offsets[rows.start];
                    for (k, i) in rows.enumerate() {
                        let row = &block[offsets[i] - base..offsets[i + 1] - base];
                        out[k] = self.force_sum::<S, false>(&shear, neighbours, i, row).0;
                    }
                },
            ),
            (Some(halves), true) => halves.fill_then(
                &self.positions,
                list,
                &self.kernel,
                pairs,
                (out, parts),
                #[inline(always)]
                |rows, block, (out, parts)| {
                    let base = offsets[rows.start];
                    for (k, i) in rows.enumerate() {
                        let row = &block[offsets[i] - base..offsets[i + 1] - base];
                        (out[k], parts[k]) = self.force_sum::<S, true>(&shear, neighbours, i, row);
                    }
                },
            ),
            _ => {
                if refresh {
                    self.fill_pairs(pairs);
                }
                let pairs = &*pairs;
                if parts.is_empty() {
                    gather(
                        out,
                        #[inline(always)]
                        |i, a| {
                            let row = &pairs[list.range(i)];
                            *a = self.force_sum::<S, false>(&shear, neighbours, i, row).0;
                        },
                    );
                } else {
                    gather2(
                        out,
                        parts,
                        #[inline(always)]
                        |i, a, b| {
                            let row = &pairs[list.range(i)];
                            (*a, *b) = self.force_sum::<S, true>(&shear, neighbours, i, row);
                        },
                    );
                }
            }
        }
    }

    /// `a_i` of [`Self::forces_loop`] and, with `BUDGET`, the Riemann-dissipation and
    /// artificial-stress parts of it; `neighbours`: velocities, volumes and pressures read
    /// through `self.list`; `row`: the kernel data of particle `i`'s pairs.
    #[inline(always)]
    fn force_sum<S: ShearForce<D>, const BUDGET: bool>(
        &self,
        shear: &S,
        (vel_j, vol_j, p_j): ForceNeighbours<'_, D>,
        i: usize,
        row: &[PairKernel<D>],
    ) -> (D::Vector, [D::Vector; 2]) {
        let (vel, rho, p) = (&self.velocities, &self.densities, &self.pressures);
        // Pairs join particles of one body, so of one material: particle i's.
        let c = self.material_of(i);
        let (rho0, c0, scheme) = (c.density, c.sound_speed, self.params.riemann);
        let (v_i, p_i, inv_rho_i) = (vel[i], p[i], 1.0 / rho[i]);
        let mut acc = D::zero();
        let mut parts = [D::zero(); 2];
        for (pk, &j) in row.iter().zip(self.list.neighbors(i)) {
            let j = j as usize;
            // SAFETY: `j` is an index of `self.list`, which made the three views
            // (`forces_loop`).
            let (vol_j, vel_j, p_j) = unsafe { (vol_j.at(j), vel_j.at(j), p_j.at(j)) };
            let vj_rho_i = vol_j * inv_rho_i;
            let u = D::dot(v_i - vel_j, pk.e);
            let p_diss = dissipative_pressure(u, rho0, c0, scheme);
            let p_star = 0.5 * (p_i + p_j) + p_diss;
            acc += pk.e * pressure_pair_factor(p_star, pk.dw, vj_rho_i);
            let (elastic, artificial) = shear.pair(i, j, pk, vj_rho_i);
            acc += elastic + artificial;
            if BUDGET {
                parts[0] += pk.e * pressure_pair_factor(p_diss, pk.dw, vj_rho_i);
                parts[1] += artificial;
            }
        }
        (acc + shear.particle(i), parts)
    }

    /// Accelerations of the current state, without loads or constraints: the force evaluation
    /// of one acoustic step, exposed for tests and diagnostics.
    pub fn evaluate_accelerations(&mut self) -> &[D::Vector] {
        self.update_pressures();
        self.compute_forces(false);
        &self.accelerations
    }

    /// Density rates `dρ/dt` (eq 11) of the current state (allocates; for tests and
    /// diagnostics).
    pub fn evaluate_density_rates(&mut self) -> Vec<f64> {
        self.update_pressures();
        self.compute_rates(None);
        self.rates.iter().map(|r| r.density).collect()
    }

    /// One acoustic step of length `dt` (eq 23–25), see the module documentation.
    pub(super) fn acoustic_step(&mut self, dt: f64) {
        let half = 0.5 * dt;
        // Eq 23 and 4: x, ρ (and τ) to the half step with the previous rates, p and V of the
        // new ρ.
        self.drift_and_pressures(half);
        // Kernel data of the half-step positions (when refreshed) and forces; loads,
        // constraints.
        self.compute_forces(self.params.refresh_kernel_data);
        if !self.loads.is_empty() {
            if self.load_accelerations.is_empty() {
                self.loads.add_accelerations(
                    self.time + half,
                    &self.masses,
                    &mut self.accelerations,
                );
            } else {
                self.load_accelerations
                    .iter_mut()
                    .for_each(|a| *a = D::zero());
                self.loads.add_accelerations(
                    self.time + half,
                    &self.masses,
                    &mut self.load_accelerations,
                );
                self.accelerations
                    .iter_mut()
                    .zip(&self.load_accelerations)
                    .for_each(|(a, &l)| *a += l);
            }
        }
        if !self.constraints.is_empty() {
            let removed = self
                .constraints
                .apply_to_accelerations_removed_force(&mut self.accelerations, &self.masses);
            self.constraint_impulse += removed * dt;
        }
        // Eq 24, with the budget's work of the step's force parts in the same pass.
        if self.params.energy_budget {
            self.kick_and_accumulate_work(dt);
        } else {
            let acc = &self.accelerations;
            gather(
                &mut self.velocities,
                #[inline(always)]
                |i, v| *v += acc[i] * dt,
            );
        }
        self.time += dt;
        // Coulomb friction between the bodies on the kicked velocities (the constraints then
        // restore any constrained component; a fully constrained partner's reaction joins the
        // constraint impulse).
        if let (Some(friction), Some(contact)) = (&mut self.contact_friction, &self.contact) {
            let momentum = contact.apply_friction(
                friction,
                &mut self.velocities,
                &self.masses,
                &self.densities,
                &self.free,
                dt,
            );
            self.constraint_impulse -= momentum;
        }
        self.constraints
            .apply_to_velocities(self.time, &mut self.velocities);
        if !self.tools.is_empty() {
            self.enforce_tool_contact(dt);
        }
        // Rates with v^{n+1}, then eq 25 and eq 20 (A_s accumulated, never reset; used by the
        // next step), in the same pass.
        self.max_speed = self.compute_rates(Some((half, dt)));
        if let Variant::Generalized { xi_g } = self.variant {
            self.accumulate_penalty(xi_g, dt);
        }
        self.acoustic_steps += 1;
        self.pair_visits +=
            (self.list.num_pairs() + self.contact.as_ref().map_or(0, |c| c.num_pairs())) as u64;
    }

    /// GNOG (arXiv 2409.11474, [`crate::generalized`]): the penalty acceleration, rotated with
    /// each particle's spin over `dt` and increased by `dt` times the pair sum of the mismatch
    /// between the velocities `v^{n+1}` and their gradients' linear prediction (a gather: each
    /// particle writes only its own accumulator). Used by the next step's forces, as ENOG's
    /// `A_s`.
    fn accumulate_penalty(&mut self, xi_g: f64, dt: f64) {
        let (list, pairs) = (&self.list, &self.pairs);
        let (v, l, vol, m) = (
            &self.velocities,
            &self.gradients,
            &self.current_volumes,
            &self.masses,
        );
        gather(
            &mut self.accumulated,
            #[inline(always)]
            |i, a| {
                let mut rate = D::zero();
                // V_j/ρ_i as V_i V_j/m_i of the half-step volumes (symmetric pair forces).
                let vi_mi = vol[i] / m[i];
                for (pk, &j) in pairs[list.range(i)].iter().zip(list.neighbors(i)) {
                    let j = j as usize;
                    let vj_rho_i = vol[j] * vi_mi;
                    rate += penalty_pair::<D>(v[i] - v[j], l[i], l[j], pk, vj_rho_i, xi_g);
                }
                *a = spin_rotation::<D>(l[i], dt) * *a + rate * dt;
            },
        );
    }

    /// Contact with the rigid tools after the kick of an acoustic step `dt` (the time already
    /// advanced): the new velocity drifts the particles for `dt` (this step's second half-drift
    /// and the next step's first, at the acoustic step of now) before it changes again, so the
    /// contact looks ahead by `dt` from `x^{n+1/2}` to `t^{n+1} + dt/2`, with the offset `dp/2`.
    fn enforce_tool_contact(&mut self, dt: f64) {
        let half_dp = 0.5 * self.kernel.h() / self.params.h_over_dp;
        // The kicked velocities, for the budget's booking after the tools changed them.
        let budget = self.params.energy_budget;
        if budget {
            self.kicked.clear();
            self.kicked.extend_from_slice(&self.velocities);
        }
        self.tools.begin_step();
        self.tools.enforce(
            self.time + 0.5 * dt,
            dt,
            |_, _| half_dp,
            half_dp,
            &self.positions,
            &mut self.velocities,
            &self.masses,
            &self.free,
            true,
        );
        self.tools.end_step(dt);
        // The tools' push leaves the body's momentum as a support's reaction does.
        self.constraint_impulse -= self.tools.step_impulse();
        if budget {
            let kicked = std::mem::take(&mut self.kicked);
            self.rebook_tool_work(&kicked, dt);
            self.kicked = kicked;
        }
    }

    /// The kick booked each force part's work on the kicked velocity `v'` as
    /// `m a_k·(v + v')/2 Δt`, but where a tool then changed `v'` to `v''` the particle keeps and
    /// drifts with `v''`: the force parts are rebooked on it (`+ m a_k·(v'' − v')/2 Δt` each)
    /// and the tools' work becomes the kinetic energy change of the whole step less the
    /// forces' work on the kept velocity (`− m a·(v'' − v')/2 Δt` added to their `½ m (v''² −
    /// v'²)`). Without it a particle held against a tool by a large force books, each step,
    /// the work `½ m (a Δt)²` its force did on a velocity the tool removes, an energy the
    /// state-based stored energies never see (the sphere on a tool wall, `hertz-impact-3d`:
    /// residuals of one to a few initial kinetic energies). The friction's velocity change is
    /// rebooked with the normal contact's (their sum is the tools' work on the body).
    fn rebook_tool_work(&mut self, kicked: &[D::Vector], dt: f64) {
        let (a, v, m) = (&self.accelerations, &self.velocities, &self.masses);
        let (parts, a_s, loads) = (
            &self.budget_parts,
            &self.accumulated,
            &self.load_accelerations,
        );
        let contact = self.contact.as_ref().map(|c| &c.accelerations[..]);
        let or_zero = |x: &[D::Vector], i: usize| x.get(i).copied().unwrap_or(D::zero());
        let (mut riemann, mut artificial, mut contact_work, mut shear, mut load_work) =
            (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut tool = 0.0;
        for (i, (&kept, &given)) in v.iter().zip(kicked).enumerate() {
            if kept == given {
                continue;
            }
            let half = (kept - given) * (0.5 * m[i] * dt);
            riemann += D::dot(parts[i][0], half);
            artificial += D::dot(parts[i][1], half);
            contact_work += D::dot(contact.map_or(D::zero(), |c| c[i]), half);
            shear += D::dot(or_zero(a_s, i), half);
            load_work += D::dot(or_zero(loads, i), half);
            tool -= D::dot(a[i], half);
        }
        self.work.riemann += riemann;
        self.work.artificial += artificial;
        self.work.contact += contact_work;
        self.work.shear += shear;
        self.work.loads += load_work;
        self.tools.add_contact_work(tool);
    }

    /// The kick of eq 24, adding the work of this step's force parts to the budget (see
    /// [`crate::energy`]).
    fn kick_and_accumulate_work(&mut self, dt: f64) {
        let (a, v, m) = (&self.accelerations, &mut self.velocities, &self.masses[..]);
        let (parts, a_s, loads) = (
            &self.budget_parts,
            &self.accumulated,
            &self.load_accelerations,
        );
        let contact = self.contact.as_ref().map(|c| &c.accelerations[..]);
        let or_zero = |x: &[D::Vector], i: usize| x.get(i).copied().unwrap_or(D::zero());
        let [riemann, artificial, contact, shear, loads] = kick_with_works::<D, 5>(
            |i| {
                [
                    parts[i][0],
                    parts[i][1],
                    contact.map_or(D::zero(), |c| c[i]),
                    or_zero(a_s, i),
                    or_zero(loads, i),
                ]
            },
            a,
            v,
            m,
            dt,
        );
        self.work.riemann += riemann;
        self.work.artificial += artificial;
        self.work.contact += contact;
        self.work.shear += shear;
        self.work.loads += loads;
    }

    /// Eq 23: `x += h v`, `ρ += h dρ/dt`, `τ += h dτ/dt` with the rates of the last step, then
    /// eq 4 (`p` and `V = m/ρ` of the new `ρ`), element-wise in one pass on the team (the
    /// drift of the step's second half is part of [`Self::compute_rates`]).
    fn drift_and_pressures(&mut self, h: f64) {
        let (mats, mat) = (&self.materials, &self.material);
        if self.params.energy_budget && self.params.riemann == RiemannScheme::Paper {
            // The volumetric-energy change the pressure jump makes over this drift
            // (Σ m p/ρ² ρ̇_jump h at the start of the drift).
            self.work.density_jump += h * self
                .densities
                .iter()
                .zip(&self.masses)
                .zip(&self.rates)
                .zip(mat)
                .map(|(((&rho, &m), r), &k)| {
                    let c = &mats[k as usize];
                    m * pressure(rho, c.density, c.sound_speed) / (rho * rho) * r.density_jump
                })
                .sum::<f64>();
        }
        let (n, v, rates, m) = (self.len(), &self.velocities, &self.rates, &self.masses);
        let columns = (
            &mut self.positions[..],
            &mut self.densities[..],
            // Empty when ENOG's output-only stress is not integrated.
            &mut self.stress[..],
            &mut self.pressures[..],
            &mut self.current_volumes[..],
            // Plastic bodies only.
            &mut self.plastic[..],
        );
        let plasticity = self.plasticity.as_ref();
        gather_columns(
            n,
            columns,
            #[inline(always)]
            |rows, (x, rho, tau, p, vol, hist)| {
                for (k, i) in rows.enumerate() {
                    x[k] += v[i] * h;
                    rho[k] += rates[i].density * h;
                    if !tau.is_empty() {
                        tau[k] += rates[i].stress * h;
                    }
                    let c = &mats[mat[i] as usize];
                    p[k] = pressure(rho[k], c.density, c.sound_speed);
                    vol[k] = m[i] / rho[k];
                    if let Some(plasticity) = plasticity {
                        return_shear_stress::<D>(plasticity, &mut tau[k], &mut hist[k], vol[k], h);
                    }
                }
            },
        );
    }
}
