//! The page `docs/reliability.md`: one row per input class the robustness tests run (with the
//! number of inputs their tables hold), the guards and their limits, checkpoints.

use super::checkpoint_inputs::{BAD_CHECKPOINTS, CHECKPOINT_REFUSED};
use super::hostile_inputs::{
    ARGUMENT_ERRORS, BAD_PART_NAMES, BAD_SCENE_NAMES, BAD_THREAD_VARIABLES, FAMILY_RANGES,
    LATE_REFUSALS, NON_REGULAR_INPUTS, OTHER_METHOD_KEYS, PATHS_THROUGH_DOTS, SCENE_RANGES,
};
use super::run_inputs::{
    extreme_inputs, malformed_inputs, ABSURD_VALUES, BAD_SCHEDULES, BLOW_UPS, CLOSED_PIPES,
    GOOD_SCHEDULES, RESULTS_REFUSED, SUMMARY_REFUSED, TOO_LARGE,
};

/// One row of the table in `docs/reliability.md`.
struct Class {
    /// The issue's item (`40.3`: issue 40, item 3; a bare number: issue 14).
    item: &'static str,
    /// What was tried.
    class: &'static str,
    /// How many inputs.
    count: fn() -> usize,
    /// What happens now (asserted by the test named).
    outcome: &'static str,
    /// The test that runs it.
    test: &'static str,
}

const CLASSES: &[Class] = &[
    Class {
        item: "1",
        class: "`--summary` onto a device, FIFO, symbolic link, the `--config` file, the \
                results or sidecar, a directory (`.`, `dir/`, `dir`), a file that is no \
                summary, an unwritable place, a path below a file",
        count: || SUMMARY_REFUSED.len(),
        outcome: "rc 2 before the run, one line naming `--summary` and why; the target and \
                  the directory unchanged, no results written",
        test: "summary_destinations_are_refused_before_the_run",
    },
    Class {
        item: "1",
        class: "`--summary` onto an earlier summary, or a new file in a directory to create",
        count: || 2,
        outcome: "rc 0; written through a temporary file of its own, renamed into place",
        test: "summary_destinations_are_refused_before_the_run",
    },
    Class {
        item: "1",
        class: "results where `--out` is a file or unwritable, or the `.h5` is not a results \
                file, a link or a FIFO, or the `.xmf` a directory",
        count: || RESULTS_REFUSED.len(),
        outcome: "rc 2 before the run, one line; nothing written or replaced",
        test: "results_destinations_are_refused_before_the_run",
    },
    Class {
        item: "2",
        class: "a second run into the same results while the first runs",
        count: || 1,
        outcome: "rc 2 at once, `another run (process N) is writing these results`; the \
                  first run's `.h5` and `.xmf` complete and consistent",
        test: "a_second_run_into_the_same_results_fails_fast",
    },
    Class {
        item: "2",
        class: "a run into the results of a run killed with SIGKILL (stale lock and `.tmp`)",
        count: || 1,
        outcome: "rc 0; the stale lock is reused, the killed run's `.tmp` (a valid HDF5 file \
                  with its snapshots) is left alone",
        test: "a_run_after_a_killed_run_reuses_its_lock_and_keeps_its_partial_file",
    },
    Class {
        item: "3, 4",
        class: "particle counts beyond memory: ring `outer_radius = 1e300`, `dp = 1e-6`, \
                `outer_radius = 1e6`; rings `dp = 1e-7`; column `resolution = 200`; UL 3D \
                plate; bad `--max-memory`",
        count: || TOO_LARGE.len(),
        outcome: "rc 2 before allocating, one line with the estimated particles and memory \
                  and the limit (or naming `--max-memory`); nothing written",
        test: "particle_counts_beyond_the_memory_limit_are_refused_before_allocating",
    },
    Class {
        item: "4",
        class: "`--max-memory` raising and lowering the limit for the same column",
        count: || 2,
        outcome: "refused (rc 2) under 0.1 GiB, accepted (rc 0, `--dry-run`) under 1 GiB",
        test: "particle_counts_beyond_the_memory_limit_are_refused_before_allocating",
    },
    Class {
        item: "5",
        class: "`snapshot_interval = 1e-300` or `1e-9`, `monitor_interval = 1e-300`, \
                `end_time = 1e300` or `1e8`, `--threads` 0, 1025 or 100000, \
                `ul_cfl_acoustic` 1 or 5",
        count: || BAD_SCHEDULES.len(),
        outcome: "rc 2 before the run, one line with the estimate and what is allowed",
        test: "absurd_schedules_end_times_and_threads_are_refused",
    },
    Class {
        item: "5",
        class: "probes recording every step beyond the memory limit; snapshots beyond the \
                free disk (estimate checked in-process)",
        count: || 2,
        outcome: "rc 2 naming `probe_interval`; the disk estimate names `snapshot_interval`",
        test: "absurd_schedules_end_times_and_threads_are_refused",
    },
    Class {
        item: "5",
        class: "`end_time = 1e8` with `--allow-long-run`, `probe_interval = 1e-300`, \
                `--threads 1024`",
        count: || GOOD_SCHEDULES.len(),
        outcome: "accepted (rc 0 with `--dry-run`)",
        test: "absurd_schedules_end_times_and_threads_are_refused",
    },
    Class {
        item: "6",
        class: "SIGINT, SIGTERM during a run",
        count: || 2,
        outcome: "rc 130 / 143; the step finished, a last snapshot at the time reached, the \
                  `.h5` completed with `status: interrupted at t = … (SIGINT)`, the summary \
                  written, no `.tmp` or lock left",
        test: "sigint_and_sigterm_finish_the_step_and_complete_the_results",
    },
    Class {
        item: "7",
        class: "`density = 1e300`, `youngs_modulus = 1e-300`, `bulk_modulus = 1e300`, \
                `c1 = 1e-300`, slab `strip_width` wider than half the slab or narrower than \
                half a spacing, `--method` contradicting the TOML's `method`",
        count: || ABSURD_VALUES.len(),
        outcome: "rc 2, one line naming the key and its allowed range",
        test: "silently_accepted_values_are_refused",
    },
    Class {
        item: "8",
        class: "runs that blow up: TL, TL-HF, UL-ENOG (plates thrown at 50 c0), MPS (slab \
                pulled at 1e9 m/s²); a run that reaches its step limit (`max_steps`)",
        count: || BLOW_UPS.len(),
        outcome: "rc 1, one line `the run stopped early: …` (inverted particle, collapsed \
                  step, lost neighbours, the step limit `max_steps` reached); the `.h5` \
                  completed with everything up to the last good step and `status: failed: …`, the summary written",
        test: "blow_ups_stop_with_a_diagnostic_and_keep_the_results",
    },
    Class {
        item: "9",
        class: "stdout closed before `sph` writes (`sph list --verbose \\| head -1`, `sph \
                list`, `sph run --dry-run`)",
        count: || CLOSED_PIPES.len(),
        outcome: "rc 0, no panic, nothing on stderr",
        test: "a_closed_stdout_is_not_an_error",
    },
    Class {
        item: "checkpoints",
        class: "`sph resume` of a missing checkpoint, one truncated (in its body, in its \
                header), a flipped bit (in the body, in the header's reserved bytes), another \
                format version, a file that is no checkpoint, the state of another case's run",
        count: || BAD_CHECKPOINTS.len(),
        outcome: "rc 2 before any work, one line naming the file and the problem; nothing \
                  written",
        test: "checkpoint::bad_checkpoints_are_refused_before_any_work",
    },
    Class {
        item: "checkpoints",
        class: "`--checkpoint-every` 0, -1, `nan`, `5 minutes`; `--checkpoint` without it; \
                `--checkpoint` naming the `--config` file, the results, the summary, a \
                directory, a file that is no checkpoint, a device; snapshots the checkpoints \
                would carry beyond the memory limit",
        count: || CHECKPOINT_REFUSED.len(),
        outcome: "rc 2 before the run, one line naming the argument; nothing written",
        test: "checkpoint::checkpoint_destinations_are_refused_before_the_run",
    },
    Class {
        item: "checkpoints",
        class: "a run resumed from its last checkpoint: TL-HF, UL-ENOG (dual stepping, \
                particles reordered), MPS (wall-time checkpoints), a scene file",
        count: || 4,
        outcome: "rc 0; the results (meta, every snapshot, probes, series, the summary but \
                  its wall-clock figures) bit-identical to the run without checkpoints, which \
                  the checkpoints do not change either",
        test: "checkpoint::{tl_hf,ul_enog_dual_stepping,mps}_resumed_run_is_bit_identical, \
               checkpoint::a_scene_run_resumes_and_a_changed_scene_is_refused",
    },
    Class {
        item: "checkpoints",
        class: "`sph resume` after the scene file was edited",
        count: || 1,
        outcome: "rc 2 before any work, one line: the scene file has changed since the \
                  checkpoint; nothing written",
        test: "checkpoint::a_scene_run_resumes_and_a_changed_scene_is_refused",
    },
    Class {
        item: "checkpoints",
        class: "a run killed with SIGKILL after a checkpoint; a run stopped with SIGINT",
        count: || 2,
        outcome: "`sph resume` continues from the last checkpoint (SIGINT: rc 130 and a \
                  checkpoint where the run stopped) and ends bit-identical to the run never \
                  stopped",
        test: "checkpoint::killed_and_interrupted_runs_resume_to_the_same_end",
    },
    Class {
        item: "—",
        class: "malformed values for every key of every case (`nan`, `inf`, `abc` for \
                numbers; `2.5`, `abc`, an overflowing integer for integers; a wrong word for \
                switches and choices)",
        count: || malformed_inputs().len(),
        outcome: "rc 2, one line naming the key; nothing written",
        test: "malformed_values_of_every_key_are_refused",
    },
    Class {
        item: "—",
        class: "`1e300`, `1e-300`, `0`, `-1` for every numeric key of every case, with one \
                method of each family it runs (`--dry-run --max-memory 1`)",
        count: || extreme_inputs().len(),
        outcome: "rc 0 (accepted) or rc 2 with one line; never a panic, abort or hang; \
                  nothing written",
        test: "extreme_values_of_every_key_never_crash",
    },
    Class {
        item: "40.1",
        class: "scene names that are paths or no names: absolute, `../`, `a/b`, a newline, a \
                tab, NUL, a backslash, empty, `.`, `..`, 300 bytes; body, constraint, tool and \
                probe names likewise; a scene named after a file whose name holds a newline",
        count: || BAD_SCENE_NAMES.len() + BAD_PART_NAMES.len() + 1,
        outcome: "rc 2 when the file is read, one line naming the key (`name`, \
                  `probe[0].name`, …); nothing written anywhere (before: the results went \
                  where the name pointed and replaced another run's)",
        test: "hostile::names_in_scene_files_are_names_not_paths",
    },
    Class {
        item: "40.2",
        class: "`--summary ./sub/../cfg.toml` (`sub` missing) with `--config cfg.toml`, two \
                missing levels, `--checkpoint new/../cfg.toml`, `..` after a link; a run \
                refused while its scene is built, with new output directories",
        count: || PATHS_THROUGH_DOTS.len() + 1,
        outcome: "rc 2 before the run: outputs compared with the inputs as the write \
                  resolves them (before: the summary replaced the `--config` file); no \
                  directory created",
        test: "hostile::outputs_are_compared_with_the_inputs_as_the_write_resolves_them",
    },
    Class {
        item: "40.3",
        class: "two probes of one name, a field written twice or unknown, a tool named like a \
                constraint",
        count: || LATE_REFUSALS.len(),
        outcome: "rc 2 before any work, not even `--out` created (before: rc 1 after the \
                  whole run, an orphan `.tmp`, no results)",
        test: "hostile::set_ups_refused_only_after_the_run_are_refused_before_it",
    },
    Class {
        item: "40.4",
        class: "an immutable earlier results file or summary, an append-only or immutable \
                results directory (`chattr`; skipped with a notice where unavailable)",
        count: || 4,
        outcome: "rc 2 before the run, one line saying why it cannot be replaced; nothing \
                  changed",
        test: "hostile::outputs_that_cannot_be_replaced_are_refused_before_the_run",
    },
    Class {
        item: "40.5",
        class: "stderr on a full disk (`2>/dev/full`) for bad input and for a run logging \
                every step; stdout on a full disk for `list`, `list --toml`, `run`, `--help`",
        count: || 6,
        outcome: "stderr: the exit status it would have (2; 0 with its results complete), \
                  never a panic (before: rc 101, only a `.tmp` left); stdout: one line on \
                  stderr and rc 1, the results complete",
        test: "hostile::logging_never_kills_a_run_and_stdout_failures_are_one_rule",
    },
    Class {
        item: "40.6",
        class: "`RAYON_NUM_THREADS` 1500, 5000, `abc`, `-1`, `2.5`; and 3",
        count: || BAD_THREAD_VARIABLES.len() + 1,
        outcome: "rc 2, one line naming `RAYON_NUM_THREADS` and the range 1-1024 (before: \
                  1,500 threads, or a panic building the pool); 3 is used",
        test: "hostile::thread_counts_from_the_environment_are_held_to_the_limit",
    },
    Class {
        item: "40.7",
        class: "a FIFO, `/dev/zero` or a 2 GiB file as `--config`, scene file, particle file \
                or checkpoint",
        count: || NON_REGULAR_INPUTS.len(),
        outcome: "rc 2 at once, one line (not a regular file; more than 16 MiB of text; a \
                  particle line over 4096 bytes; a checkpoint's header announcing more than \
                  the memory limit); before: a hang or the whole file read",
        test: "hostile::inputs_that_are_not_regular_files_or_too_large_are_refused_at_once",
    },
    Class {
        item: "40.8",
        class: "SIGHUP, SIGQUIT, SIGUSR1 during a run",
        count: || 3,
        outcome: "SIGHUP, SIGQUIT: rc 129, 131, the step finished and the results completed \
                  with the signal in the status (before: no results); SIGUSR1: a progress \
                  line, the run goes on",
        test: "hostile::hangup_and_quit_keep_the_results_and_usr1_reports_progress",
    },
    Class {
        item: "40.9",
        class: "a 3.5 GiB column and a 63 MB one under `ulimit -v 1048576` (1 GiB)",
        count: || 2,
        outcome: "the first rc 2 before the run naming the address-space limit (before: an \
                  abort, rc 134), the second accepted",
        test: "hostile::the_memory_guard_honours_the_address_space_limit",
    },
    Class {
        item: "40.10",
        class: "10,002 probes",
        count: || 1,
        outcome: "rc 2 before any work: at most 10,000 (before: 200,000 probes took over a \
                  minute to write)",
        test: "hostile::probe_counts_are_limited",
    },
    Class {
        item: "40.11, 40.12",
        class: "scene files with `density = 1e300`, `youngs_modulus = 1e-300`, `cfl = 10`, \
                `h_over_dp = 50`, a tool at 1e300 m/s, `zeta` with tl, a body of 2 particles, \
                a body too soft for its punch; UL `cfl_acoustic = 10`, MPS `courant = 10`, \
                `epsilon` with ul-enog",
        count: || SCENE_RANGES.len() + FAMILY_RANGES.len(),
        outcome: "rc 2 before the run, one line naming the file, line and key \
                  (`material.density`, `numerics.cfl`, `tool[0].speed`, `body[0].dp`) with \
                  short numbers (`1e300`); before: rc 0, or rc 1 mid-run",
        test: "hostile::scene_files_get_the_range_checks_of_case_keys",
    },
    Class {
        item: "40.12",
        class: "case keys of another method (`zeta` with tl, `as_epsilon` with ul-enog, `cfl` \
                with ul-og); two soft discs thrown far faster than their sound speed",
        count: || OTHER_METHOD_KEYS.len() + 1,
        outcome: "rc 2 before the run naming the key and its methods; the discs: the run \
                  cannot take its first step (before: rc 1 at step 0)",
        test: "hostile::keys_of_another_method_and_first_steps_that_cannot_be_taken_are_refused",
    },
    Class {
        item: "40.14",
        class: "a file named like a case in the working directory; `./NAME`; a parameter \
                file of `sph list --toml` run as a scene",
        count: || 3,
        outcome: "the name refused as ambiguous (rc 2), `./NAME` runs the file; the \
                  parameter file: rc 2 saying what it is and the command that runs it",
        test: "hostile::a_case_name_that_is_also_a_file_is_ambiguous",
    },
    Class {
        item: "40.15",
        class: "`--threads -1`, `--threads abc`, `--compress=-1`, an unknown flag, a flag \
                without its value, no case, no subcommand, an unknown subcommand, a bad \
                `--log-every`, a non-UTF-8 argument",
        count: || ARGUMENT_ERRORS.len() + 1,
        outcome: "rc 2, one line (before: clap's usage text); `--help` still prints help",
        test: "hostile::argument_errors_are_one_line",
    },
];

/// `docs/reliability.md`: the exit statuses, a row per class of [`CLASSES`], the guards and
/// the checkpoints.
pub fn render_doc() -> String {
    use sph_cases::guard::{MAX_MONITOR_SAMPLES, MAX_PARTICLE_STEPS, MAX_SNAPSHOTS, MAX_STEPS};
    use sph_core::budget::{BYTES_PER_PARTICLE_2D, BYTES_PER_PARTICLE_3D, DEFAULT_MEMORY_FRACTION};
    use sph_core::diagnostics::MIN_DT_RATIO;
    let mut s = String::new();
    s.push_str(
        "# Reliability\n\n\
         <!-- Generated by `SPH_UPDATE_DOCS=1 cargo test -p sph-cases --test robustness \
         reliability_doc_is_current`; do not edit by hand. -->\n\n\
         How `sph` behaves on hostile but fair input (issues 14 and 40). Every row is run by \
         the test named in `crates/sph-cases/tests/robustness.rs` (`checkpoint::…`: in \
         `crates/sph-cases/tests/checkpoint.rs`; `hostile::…`: in \
         `crates/sph-cases/tests/hostile.rs`), part of `cargo test --workspace`, which \
         asserts the outcome; this page is rendered from the same tables, and a test fails \
         when it is out of date. Regenerate it with\n\n\
         ```sh\n\
         SPH_UPDATE_DOCS=1 cargo test -p sph-cases --test robustness reliability_doc_is_current\n\
         ```\n\n\
         ## Exit status\n\n\
         | status | meaning |\n\
         |---|---|\n\
         | 0 | completed (or `--dry-run`: checked and estimated, nothing run or written) |\n\
         | 1 | the run started and failed (blow-up, write error): the results file is completed with everything up to the last good step and `status: failed: …`; or stdout could not be written (a full disk; a reader that closed the pipe is no error), the results complete |\n\
         | 2 | bad input: one line on stderr naming the argument or key and what is allowed; nothing written |\n\
         | 129, 130, 131, 143 | interrupted by SIGHUP, SIGINT, SIGQUIT, SIGTERM: the current step finished, the file completed with `status: interrupted at t = …`, the summary written (a second signal ends the process at once) |\n\n\
         Every message is one line on stderr; a failed write to stderr (a closed terminal, a \
         full disk) is ignored, so logging never ends a run or changes its status. SIGUSR1 or \
         SIGUSR2 prints a progress line and the run goes on.\n\n\
         ## Inputs tried\n\n\
         | issue item | input class | inputs | outcome | test |\n\
         |---|---|---|---|---|\n",
    );
    let mut total = 0;
    for c in CLASSES {
        let n = (c.count)();
        total += n;
        s.push_str(&format!(
            "| {} | {} | {} | {} | `{}` |\n",
            c.item, c.class, n, c.outcome, c.test
        ));
    }
    s.push_str(&format!("| | **total** | **{total}** | | |\n\n"));
    s.push_str(&format!(
        "## Guards and their limits\n\n\
         | guard | where | limit |\n\
         |---|---|---|\n\
         | particles | the generators of `sph_geometry::generate` and particle files, before they allocate (`sph_core::budget`) | estimated peak memory = particles × {b2} B (2D) or {b3} B (3D), measured per method (table in `sph_core::budget`), at most {frac:.0} % of the least of the memory available (`MemAvailable`), what the memory cgroup leaves at every level of its hierarchy (v1, v2) and what `ulimit -v` / `ulimit -d` leave (beyond the process's size and its threads' reservations), or `--max-memory GIB`; the counts of one run add up; never more than 2³² − 1 particles |\n\
         | snapshots | `sph_cases::guard`, before the run | at most {snap} snapshots, and their estimated size within the free space of the output directory |\n\
         | monitor samples | `sph_cases::guard` | at most {mon} |\n\
         | probe samples | `sph_cases::guard` | their memory within the limit left by the particles |\n\
         | work | `sph_cases::guard` | at most {ps:e} particle-steps (about a day on 2 cores) unless `--allow-long-run`; never more than {st:e} steps (time resolution) |\n\
         | threads | `sph` | `--threads`, else `RAYON_NUM_THREADS`, else every core: 1 to 1024 either way |\n\
         | probes | the solvers' `with_probes` (`sph_core::scene::check_probes`) | at most {probes} per body, names unique |\n\
         | names | `sph_core::error::check_name`, when a scene is read and when a solver is given probes, tools or named constraints | 1 to {name_bytes} bytes, no `/` or `\\`, no control character, not `.` or `..` |\n\
         | inputs | `sph_output::input` | regular files only (a FIFO or device refused at once, no open that waits); scene and parameter files at most {text} bytes; particle files streamed against the memory budget, lines of at most 4096 bytes; a checkpoint's header read first, its state within the memory limit |\n\
         | checkpoints | `sph_driver::guard`, before the run | the snapshots they carry within the memory the particles and probes leave; two checkpoints (those snapshots and at most {sb} B of solver state per particle) within the free space of their directory |\n\
         | densities, moduli | `sph_materials::ElasticConstants` (and the Mooney–Rivlin constants), for cases, scene files and library calls alike | 1e-3 to 1e6 kg/m³; 1e-3 to 1e13 Pa |\n\
         | numerical parameters | `TlParams`, `UlParams`, `MpsParams::validate`, the ranges the case keys show | e.g. `h_over_dp` 0.5 to 3, CFL and Courant numbers between 0 and 1; a key of another method refused |\n\
         | bodies, tools | `sph-scene`, the TL solver | a body at least 3 particles across; a tool slower than the body's sound speed |\n\
         | blow-up | every solver's step, and the driver before the run (`Solver::check_time_step`) | `J = det F ≤ 0` (UL: `ρ ≤ 0`) or a non-finite state stops the run; so does a stable step below {ratio} of the acoustic step at rest (`sph_core::diagnostics::MIN_DT_RATIO`), checked in UL's acoustic sub-steps too; a state that cannot take its first step is refused before the run |\n\
         | outputs | `sph_output::safety` and `sph_cases::preflight` | checked as the write resolves them (`..` after a directory to be created, links); replaced only if a regular file a run wrote (results file, XDMF, earlier summary) that can be replaced (not immutable or append-only, not another user's in a sticky directory); never an input, a link, device, FIFO or directory; writability and renames probed before the run; no directory created before every check passed; one temporary file per writer (`<name>.<pid>-<k>.tmp`, `O_EXCL`); one writer per results file (`flock` on `<name>.h5.lock`) |\n\n\
         `sph run … --dry-run` prints the estimates (particles, memory, steps, particle-steps, \
         snapshots, disk, probe memory) without running or writing anything.\n\n\
         ## Checkpoint and restart\n\n\
         | flag | meaning |\n\
         |---|---|\n\
         | `sph run … --checkpoint-every INTERVAL` | write the full state of the run every \
         INTERVAL of simulated time (`0.01`) or wall time (`5min`, `90s`), at the first snapshot \
         or monitor time after it (checkpoints never change the steps a run takes), and when \
         SIGINT, SIGTERM, SIGHUP or SIGQUIT stops the run |\n\
         | `sph run … --checkpoint FILE` | where (default `<out>/<case>-<method>.ckpt`); \
         replaces only an earlier checkpoint, never an input, the results, the summary, a link \
         or a device; one run per checkpoint (`flock` on `FILE.lock`) |\n\
         | `sph resume FILE [--threads N] [--max-memory GIB] [--log-every S]` | rebuild the run \
         the checkpoint records (case or unchanged scene file, method, every parameter, files; \
         the thread count of the first run unless `--threads`), restore its state and continue \
         to the end time; same exit statuses as `sph run` |\n\n\
         A checkpoint holds the solver's state (positions, velocities; TL: `F`, `Ḟ`, the last \
         accelerations; UL: density, shear stress, the ENOG accumulator, the rates of the next \
         half-step, the particle order; MPS: `F`, the stress terms, forces and accelerations; \
         time, step count, probe and series records), never the neighbour lists (rebuilt); the \
         driver's schedule, monitor samples and every snapshot written so far; the run's meta; \
         its format version ({ckv}) and an FNV-1a checksum. It is written to a temporary file \
         created exclusively beside it, synced and renamed over the previous one, which stays \
         whole until then. A resumed run re-creates the results file: the snapshots from the \
         checkpoint, then the rest of the run, written like any run's (temporary file, rename, \
         lock), so the file is never left half-continued and ends bit-identical to the run \
         never stopped (wall-clock figures aside). A run killed with SIGKILL loses the work \
         since its last checkpoint; its own `<name>.h5.<pid>-<k>.tmp` stays (a valid HDF5 \
         file with every snapshot written before the kill). A checkpoint grows with the \
         snapshots it carries (as large as the results file so far).\n",
        ckv = sph_driver::checkpoint::FORMAT_VERSION,
        sb = sph_driver::guard::STATE_BYTES_PER_PARTICLE,
        b2 = BYTES_PER_PARTICLE_2D,
        b3 = BYTES_PER_PARTICLE_3D,
        frac = DEFAULT_MEMORY_FRACTION * 100.0,
        snap = MAX_SNAPSHOTS,
        mon = MAX_MONITOR_SAMPLES,
        ps = MAX_PARTICLE_STEPS,
        st = MAX_STEPS,
        ratio = MIN_DT_RATIO,
        probes = sph_core::scene::MAX_PROBES,
        name_bytes = sph_core::error::MAX_NAME_BYTES,
        text = sph_output::input::MAX_TEXT_BYTES,
    ));
    s
}
