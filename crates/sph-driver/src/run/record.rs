//! What a run records: the monitor's samples and the run record with its summary.

use super::*;

/// One sample of the run monitor.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct MonitorSample {
    /// Simulated time.
    pub time: f64,
    /// Disorder indicator statistics over the particles.
    pub disorder: DisorderStats,
    /// Kinetic energy (NaN if the method has none).
    pub kinetic: f64,
    /// Strain energy (NaN if the method has none).
    pub strain: f64,
    /// The energy budget, for methods that keep one (in the summary as
    /// `monitor.energy_budget`).
    #[serde(skip)]
    pub budget: Option<EnergyBudget>,
    /// Connected pieces of the particles' neighbour graph (from the field `fragment`), for
    /// methods that label them: a body that breaks apart adds pieces.
    pub pieces: Option<usize>,
    /// The output fields sampled at the probes that ask for some ([`sph_core::Probe::fields`]):
    /// for each such probe in order, each of its fields' components (1, 3 or 9), flattened.
    #[serde(skip)]
    pub probe_fields: Vec<f64>,
}

/// What a run did.
#[derive(Clone, Debug, Default)]
pub struct RunRecord {
    /// Particles.
    pub particles: usize,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached.
    pub time: f64,
    /// Wall time of the whole run, output included.
    pub wall_seconds: f64,
    /// Wall time spent inside `Solver::step`.
    pub solver_seconds: f64,
    /// Monitor samples.
    pub monitor: Vec<MonitorSample>,
    /// The error that stopped the run early, if any.
    pub failure: Option<String>,
    /// The signal that interrupted the run, if one did (the run stopped cleanly).
    pub interrupted: Option<usize>,
    /// The estimates made before the run ([`crate::guard::Estimate`]).
    pub estimate: Option<crate::guard::Estimate>,
    /// The results file, if one was written.
    pub file: Option<PathBuf>,
    /// The `.pvd` collection of the per-frame VTU files, if they were written
    /// ([`crate::RunOptions::vtu`]).
    pub collection: Option<PathBuf>,
    /// Neighbour pairs visited by the force evaluations ([`Solver::pair_visits`]).
    pub pair_visits: Option<u64>,
}

impl RunRecord {
    /// `completed`, `failed: <diagnostic>` or `interrupted at t = <time> s (<signal>)`.
    pub fn status(&self) -> String {
        match (&self.failure, self.interrupted) {
            (Some(e), _) => format!("failed: {e}"),
            (None, Some(sig)) => {
                format!("interrupted at t = {} s ({})", self.time, signal_name(sig))
            }
            (None, None) => "completed".to_string(),
        }
    }

    /// Particle-steps per second of the solver (time inside `step` only).
    pub fn particle_steps_per_second(&self) -> f64 {
        if self.solver_seconds > 0.0 {
            self.particles as f64 * self.steps as f64 / self.solver_seconds
        } else {
            0.0
        }
    }

    /// Largest disorder indicator seen.
    pub fn max_disorder(&self) -> f64 {
        self.monitor
            .iter()
            .map(|m| m.disorder.max)
            .fold(0.0, f64::max)
    }

    /// Relative change of total energy between the first and the last monitor sample, where the
    /// method has a strain energy. `None` for a run that starts at rest (an initial energy
    /// below 10⁻⁹ of the largest sampled, round-off of a state without motion or strain): a
    /// change relative to it is no figure (it read 10²² on the MPS cantilever under gravity);
    /// such a run's energy is accounted for by its budget, where the method keeps one.
    pub fn energy_drift(&self) -> Option<f64> {
        let (a, b) = (self.monitor.first()?, self.monitor.last()?);
        let (e0, e1) = (a.kinetic + a.strain, b.kinetic + b.strain);
        let largest = self
            .monitor
            .iter()
            .map(|m| m.kinetic + m.strain)
            .fold(0.0, f64::max);
        (e0.is_finite() && e1.is_finite() && e0 > 1e-9 * largest).then(|| (e1 - e0) / e0)
    }

    /// The energy-budget residual (`total − initial total`, see [`EnergyBudget`]) over the
    /// initial total, at the last monitor sample and its largest magnitude over the samples,
    /// where the method keeps a budget.
    pub fn energy_residual(&self) -> Option<(f64, f64)> {
        let rel = |b: &EnergyBudget| b.residual() / b.initial_total;
        let last = self.monitor.last()?.budget.as_ref()?;
        if last.initial_total.is_nan() || last.initial_total <= 0.0 {
            return None;
        }
        let max = self
            .monitor
            .iter()
            .filter_map(|m| m.budget.as_ref().map(rel))
            .fold(0.0, |m: f64, r| if r.abs() > m.abs() { r } else { m });
        Some((rel(last), max))
    }

    /// The figures every case reports (issue: case, method, particles, steps, wall_seconds,
    /// particle_steps_per_second, max_disorder, energy_drift), plus the status; for methods
    /// with an energy budget also `energy_residual` (at the end) and `energy_residual_max`
    /// (largest magnitude over the monitor samples), both relative to the initial total, and
    /// the budget's terms over time under `monitor.energy_budget`; for methods that label
    /// connected pieces (field `fragment`) `pieces_initial`, `pieces_max` and
    /// `first_break_time` (the first monitor sample with more pieces than at the start).
    pub fn standard_summary(&self, case: &str, method: &str) -> Map<String, Json> {
        let mut m = Map::new();
        m.insert("case".into(), json!(case));
        m.insert("method".into(), json!(method));
        m.insert("particles".into(), json!(self.particles));
        m.insert("steps".into(), json!(self.steps));
        m.insert("time_reached".into(), json!(self.time));
        m.insert("wall_seconds".into(), json!(self.wall_seconds));
        m.insert("solver_seconds".into(), json!(self.solver_seconds));
        m.insert(
            "particle_steps_per_second".into(),
            json!(self.particle_steps_per_second()),
        );
        m.insert("threads".into(), json!(rayon::current_num_threads()));
        m.insert("pair_visits".into(), json!(self.pair_visits));
        m.insert("max_disorder".into(), finite_or_null(self.max_disorder()));
        m.insert(
            "energy_drift".into(),
            self.energy_drift().map_or(Json::Null, finite_or_null),
        );
        let pieces: Vec<usize> = self.monitor.iter().filter_map(|s| s.pieces).collect();
        if let (Some(&p0), Some(&max)) = (pieces.first(), pieces.iter().max()) {
            m.insert("pieces_initial".into(), json!(p0));
            m.insert("pieces_max".into(), json!(max));
            let broke = self
                .monitor
                .iter()
                .find(|s| s.pieces.is_some_and(|p| p > p0))
                .map(|s| s.time);
            m.insert(
                "first_break_time".into(),
                broke.map_or(Json::Null, |t| json!(t)),
            );
        }
        if let Some((last, max)) = self.energy_residual() {
            m.insert("energy_residual".into(), finite_or_null(last));
            m.insert("energy_residual_max".into(), finite_or_null(max));
        }
        m.insert("status".into(), json!(self.status()));
        let mut monitor = json!({
            "time": self.monitor.iter().map(|s| s.time).collect::<Vec<_>>(),
            "disorder_max": self.monitor.iter().map(|s| finite_or_null(s.disorder.max)).collect::<Vec<_>>(),
            "disorder_p99": self.monitor.iter().map(|s| finite_or_null(s.disorder.p99)).collect::<Vec<_>>(),
            "kinetic_energy": self.monitor.iter().map(|s| finite_or_null(s.kinetic)).collect::<Vec<_>>(),
            "strain_energy": self.monitor.iter().map(|s| finite_or_null(s.strain)).collect::<Vec<_>>(),
        });
        if self.monitor.iter().any(|s| s.pieces.is_some()) {
            monitor["pieces"] = json!(self.monitor.iter().map(|s| s.pieces).collect::<Vec<_>>());
        }
        if let Some(budget) = budget_series(&self.monitor) {
            monitor["energy_budget"] = budget;
        }
        m.insert("monitor".into(), monitor);
        m
    }
}

/// The budget's terms and notes over the monitor samples, `{name: [values]}` plus `residual`,
/// when every sample has a budget.
fn budget_series(samples: &[MonitorSample]) -> Option<Json> {
    let budgets: Vec<&EnergyBudget> = samples
        .iter()
        .map(|s| s.budget.as_ref())
        .collect::<Option<_>>()?;
    let first = budgets.first()?;
    let mut out = Map::new();
    for &(name, _) in first.terms.iter().chain(&first.notes) {
        let v: Vec<Json> = budgets
            .iter()
            .map(|b| b.get(name).map_or(Json::Null, finite_or_null))
            .collect();
        out.insert(name.into(), Json::Array(v));
    }
    let residual: Vec<Json> = budgets
        .iter()
        .map(|b| finite_or_null(b.residual()))
        .collect();
    out.insert("residual".into(), Json::Array(residual));
    out.insert("initial_total".into(), finite_or_null(first.initial_total));
    Some(Json::Object(out))
}

/// `SIGINT`, `SIGTERM`, … for the signals a run is stopped with; `signal N` otherwise.
pub fn signal_name(sig: usize) -> String {
    match sig {
        1 => "SIGHUP".into(),
        3 => "SIGQUIT".into(),
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        n => format!("signal {n}"),
    }
}

/// A JSON number, or null for NaN/∞ (JSON has no such numbers).
pub fn finite_or_null(x: f64) -> Json {
    if x.is_finite() {
        json!(x)
    } else {
        Json::Null
    }
}
