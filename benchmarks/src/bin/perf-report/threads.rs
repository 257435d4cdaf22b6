//! The prose of docs/performance.md on where the time of a step goes and what the thread team,
//! the loop fusions and the instruction-level work changed (profiles and measurements, each with
//! its command).

use std::fmt::Write as _;

/// Where the time of a small 2D step goes, and what the thread team changed (profiles, not a
/// benchmark: the commands are given, the numbers are those of the commit that introduced the
/// team).
pub(crate) fn threads_section(md: &mut String) {
    writeln!(
        md,
        "## Where the time goes, and the thread team\n\n\
         Profiles of the 1,612-particle plate (H/dp 10, h = 1.3 dp, `perf record` of `sph run \
         oscillating-plate-2d --method M --set h_over_dp=1.3 --set end_time=0.1 --no-output \
         --threads 1`, share of the samples). **TL**: the stress divergence (eq 20) 28 %, \
         the deformation rate (eq 22) 23 %, the stress update (first Piola–Kirchhoff and the \
         correction) 19 %, the half steps and the kick 6 %, the speed maximum for the time \
         step 5 %, the finiteness check 3 %. **UL-ENOG** (dual stepping): the kernel-data \
         refresh of every acoustic sub-step 30 %, the force gather 25 %, the rate gather \
         (continuity, velocity gradient, ENOG's Laplacian) 16 %, the neighbour search of the \
         advection steps 6 %, the pair halves of a new list (`PairSymmetry::new`, serial) \
         3 %, element-wise updates 3 %.\n\n\
         **The refresh, measured further.** Instructions and simulated cache misses of the \
         same UL run to t = 0.02 s (`valgrind --tool=cachegrind --cache-sim=yes`, 32 KiB \
         first-level data cache): the refresh executes 24 % of the instructions (1.84·10⁹ of \
         7.60·10⁹; the force gather 21 %, the rate gather 16 %) and makes 74 % of the \
         first-level write misses: its 40-byte records (then; 32 bytes since the change below) of about 34,000 pairs, 1.3 MB per \
         sub-step, do not stay in a core's cache between the refresh, the force gather and the \
         rate gather. Three rewrites with the same bits were measured against the build \
         without them (one thread, 0.25 s simulated, the two builds interleaved, three runs \
         each, quiet machine) and dropped: (1) the pairs of the refresh four at a time through \
         AVX (`vsqrtpd`, `vdivpd` on 256-bit registers, selected at run time): 9.37 / 9.51 / \
         10.25 s against 9.20 / 9.71 / 9.44 s, no gain; (2) the same batches over whole rows \
         instead of the symmetric halves: 10.30 / 10.84 / 10.31 s against 9.24 / 8.42 / \
         9.24 s, 12 % slower; (3) no refresh pass, the force gather computing its row's pair \
         data (twice the kernel evaluations of the halves) and storing them for the rate \
         gather: 12.63 / 11.71 / 12.13 s against 9.63 / 9.17 / 9.99 s (energy budget off in \
         both), 25 % slower. **Smaller records, kept:** the pair record no longer stores `W` \
         (only OAS's artificial stress, contact, GM's penalty and the disorder indicator read \
         it; they evaluate the kernel at the stored distance, the same bits), 32 instead of 40 \
         bytes in 2D and 40 instead of 48 in 3D, and the refresh no longer evaluates `W`. \
         Intel Xeon, the other runs on the machine stopped, old and new build interleaved: \
         UL-ENOG plate 2D to 0.25 s, one thread 3.96 → 3.64 s (3 runs each, ranges 3.91–3.96 \
         and 3.63–3.66), two threads 2.41 → 2.29 s (median of 5, 2.39–2.44 and 2.27–2.31); \
         UL-ENOG 3D plate at H/dp 3 (`sph run oscillating-plate-3d --method ul-enog --set \
         resolution=3 --set end_time=0.004 --no-output --threads 2`) 50.7 → 41.7 s (3 runs \
         each, 47.2–50.7 and 41.6–44.6), −18 %. The results files of eleven scenes (UL-ENOG, \
         OAS with refreshed and frozen kernel data, TL-GM stored (2D plate) and recomputed \
         (bending column), the UL-ENOG and MPS rings before they touch, the UL-OAS rings \
         through their impact (contact work 3.46·10⁻³), the MPS pressurised ring and slab, the \
         2D ball–plate, the Hertz impact) are equal to the previous build's, every dataset. Single precision would \
         change results at round-off and was not tried. **No serial tail after the \
         refresh, kept:** the slots whose mirror lies in another task's block were copied on \
         the calling thread after the parallel region; they are now computed in their own \
         block (the same bits as the copy). They are a fifth of the pairs of the 3D plate at \
         H/dp 3 (457,688 of 2,293,108) and 5 % of the 2D plate's (1,481 of 28,936). Same \
         machine and method, interleaved: 3D plate to 0.002 s, two threads, 29.5 → 28.4 s \
         (3 runs each, 28.8–30.4 and 27.3–28.9); 2D plate to 0.25 s, two threads, 2.45 → \
         2.39 s (median of 5, 2.34–2.53 and 2.38–2.44). **The two-thread 2D runs wait, \
         measured:** `perf record` of the UL-ENOG plate on two threads (0.25 s): the helper \
         spins 12–14 % of all samples and the leader waits in `run_tasks` 6 %, while the \
         serial work of the leader (the pair halves of a new list 2.0 %, the energy budget's \
         work sums 2.1 %, the rebuild and cell list 1.1 %) is about 5 %; the TL plate: leader \
         waiting 14 %, helper spinning 11 %. Three remedies were built, measured (Intel Xeon, \
         the machine otherwise stopped, interleaved, 0.25 s simulated) and dropped: (1) four \
         tasks per thread instead of one, claimed dynamically: UL-ENOG two threads 2.48 s \
         (2.41–2.57) against 2.46 s (2.36–2.58), median of 5; (2) the TL pair loops cut at \
         equal numbers of pairs instead of particles: 0.70 s against 0.70 s (median of 5); \
         (3) the energy budget's per-particle work computed in the (parallel) kick loop and \
         summed in particle order after it (same bits): two threads 2.62 s (2.52–2.71) against \
         2.59 s (2.50–2.64), median of 7, one thread 4.52 against 4.47 s (3 runs). So the \
         waiting is not the cut of the loops; what is left is entering and leaving them (not \
         measured separately): a sub-step of the 1,612-particle plate is five parallel loops \
         of 15–30 µs each on two threads. **One loop fewer, measured and dropped:** the \
         drift of the sub-step's first half fused into the refresh's parallel region (each \
         computed pair drifts its two positions where it needs them, `x_j + h v_j`, the same \
         bits; the drifted positions go to a second buffer; results files of ten UL scenes \
         equal dataset by dataset), Intel Xeon, the machine otherwise stopped, interleaved, \
         0.25 s simulated: two threads 2.88 s (2.82–2.91) against 2.84 s (2.74–2.91), median \
         of 7; one thread 4.76 s (4.66–5.07) against 4.79 s (4.52–4.94), median of 5; 3D \
         plate at H/dp 3 to 0.002 s on two threads 31.9 s (30.9–32.1) against 30.8 s \
         (30.8–32.9), 3 runs. So a parallel loop's entry and exit is not what two threads \
         lose either. **Where two threads lose, counted:** a build with time-stamp counters \
         around each loop and each task (not kept; 2.6 GHz counter), UL-ENOG plate on two \
         threads to 0.25 s: 77,000 loops (14,581 sub-steps, 928 advection steps) of 71,000 \
         cycles (27 µs) on average; the leader's task 66,000 cycles, the helper's 66,400, \
         their difference 7,000 on average (10 % of a loop), the loop's end beyond the longer \
         task 1,300 (2 %), the helper's start 1,300 cycles after the loop opens. The loops \
         are 2.10 s of the 2.64 s run (80 %); the other 0.54 s is the leader's serial work \
         between them (the pair halves of each new list, the cell list, the energy budget's \
         sums, the constraints, the monitor), while the helper spins. The two tasks together \
         are 3.92 s of work: loops split perfectly and entered for free would make the run \
         1.96 + 0.54 = 2.50 s instead of 2.64 s. So the serial fifth, not the loops' entry and \
         exit, keeps this plate from scaling, and it is many small pieces: of all samples of \
         both threads (`perf record`, same run), the leader's functions other than the loop \
         bodies have 9.5 %: `PairSymmetry::new` 2.1 %, the sub-step's inline serial work \
         (energy budget sums, constraints) 1.8 %, libm's `hypot`/`atan2`/`sincos` 1.6 % (the \
         helper has 0.7 % of them: they are partly in the monitor's parallel loops), the cell \
         list, reordering and list components 1.5 %. TL plate, same \
         run: 95,000 loops (9,493 steps) of 17,700 cycles (6.8 µs), leader 16,100, helper \
         15,000, difference 2,600 (15 %), end beyond the longer task 860 (5 %); the loops \
         are 0.65 s of 0.73 s (89 %). On \
         the same machine and day the two dropped rewrites of the refresh above were \
         repeated with the same outcome: the force gather computing its pairs' data, one \
         thread 5.20 s against 4.32 s, two threads 3.10 s against 2.61 s (median of 5 each, \
         +20 %); the refresh in groups of four pairs in the baseline (SSE2) build, 4.44 s \
         against 4.39 s (median of 5; the compiler kept one scalar square root per pair). \
         The energy budget's 12 % is per-pair work, not serial: it costs the same share on one \
         thread (4.31 s against 3.85 s with `--set energy_budget=false`, median of 5) as on \
         two (2.64 s against 2.36 s), and `perf` puts it in the force gather (35 % more samples \
         there). Skipping ENOG's zero pair terms (its shear is per particle; the same bits) \
         gained nothing: one thread 4.29 s against 4.23 s, two 2.56 s against 2.54 s (median \
         of 5 each). TL's stress divergence `Σ_j (S_i + S_j) V_j ∇W_ij` summed as \
         `S_i G_i + Σ_j S_j V_j ∇W_ij` with `G_i = Σ_j V_j ∇W_ij` fixed with the reference \
         data (one matrix–vector product per particle instead of a matrix sum per pair; the \
         rounding changes): twisting column (`case-timings`' row, to 0.1 s) one thread 2.42 s \
         against 2.46 s (median of 3), two threads 1.66 s against 1.68 s (median of 5), TL \
         plate 0.99 s against 0.99 s: 1–3 %, not worth changing every result at round-off; \
         dropped. `PairSymmetry::new` without a branch per slot (compaction by index, \
         conditional moves): 516 against 527 of about 20,000 `perf` samples of the UL plate on \
         one thread, no gain; dropped. \
         The energy budget costs 12 % on two threads (`--set energy_budget=false`: 2.22 s \
         against 2.49 s, 4 runs each), most of it in the force gather's per-pair sum of the \
         Riemann dissipation (moving its serial work sums into the kick loop changed nothing, \
         above). The serial `PairSymmetry::new` of each rebuild was also built per block \
         on the team, the pairs whose mirror lies in another block computed instead of \
         copied after the parallel region (same bits; Intel Xeon, the other runs on the \
         machine stopped, the two builds interleaved, 0.25 s simulated): two threads \
         2.44 s (2.42–2.45, median of 5) against 2.41 s (2.38–2.43), one thread 3.99 s \
         (3.97–3.99, 3 runs) against 3.93 s (3.89–3.96): the per-block construction costs more \
         than the serial one it replaces, dropped.\n\n\
         **The twisting column, and the bounds checks of the pair loops.** `perf record` of \
         the anchor run on one thread (`sph run twisting-column-3d --method tl-hf --set \
         h_over_dp=1.3 --set resolution=10 --set end_time=0.5 --set nu=0.45 --set \
         omega0=400 --set clamp_layers=1 --set cfl=0.5 --no-output --threads 1`, Intel Xeon, \
         2026-12-03): the HF acceleration (eq 20 with the Laplacian shear, eq 27) 49 %, the \
         deformation rate (eq 22) 29 %, the disorder indicator of the monitor's 200 samples \
         6 % (one sample costs about 1.7 HF passes: two square roots and a kernel value per \
         pair, a latency chain), the stress update 5 % and the cube root of its `J^(−2/3)` \
         another 5 %, the half steps 2 %. The neighbour reads `v[j]` of the main pair loops \
         (UL force and rate gathers and refresh positions; TL stress divergence, HF \
         acceleration, deformation rate, GM penalty; MPS deformation gradient, forces, \
         stabilisation; the disorder indicator and affine fit) were bounds-checked per read; \
         those checks are gone (`NeighborList::values` checks the length once against the \
         list's largest index, kept with the list; the shear variants' own pair terms and the \
         refresh's slot reads keep theirs), the same bits (the results \
         files of sixteen scenes of all seven methods equal dataset by dataset). Instructions: \
         the table above (builds 8a8e284 and a472b77: TL plate −7.2 %, UL-ENOG plate −7.1 %, \
         twisting column −8.9 %; per function, twisting column with the default monitor to \
         t = 0.02 s: HF acceleration −13 %, deformation rate −6.6 %, disorder −4.9 %; UL-ENOG \
         plate: force gather −15 %, rate gather −14 %), the MPS cantilever plate \
         (`valgrind --tool=cachegrind --cache-sim=no sph run cantilever-plate-2d --method mps \
         --set end_time=0.02 --no-output --threads 1`) 6.746·10⁹ → 6.405·10⁹ (−5.1 %). Their wall time could not be resolved that \
         day: the machine ran at about half its speed of 2026-12-02 with ±20 % between \
         repeats of the same binary (`sph run oscillating-plate-2d --method ul-enog --set \
         h_over_dp=1.3 --set end_time=0.25 --no-output --threads 1`, nine interleaved runs \
         each: 7.01–10.31 s before, 6.90–10.19 s after; the twisting column above with \
         `end_time=0.1`, eight each: 3.90–5.52 s and 3.96–5.80 s; two copies of one binary \
         running at once, one per core, the cores swapped each round, TL plate to 0.25 s: \
         their ratio 0.77–1.33 over 16 rounds, median 1.05); kept for the instructions, to be timed on a \
         quiet machine.\n\n\
         **AVX2 copies of the particle loops.** The release build targets plain x86-64 \
         (SSE2). A whole-program build with `RUSTFLAGS=\"-C target-feature=+avx2,+fma\"` of \
         503ea67 executes 12–18 % fewer instructions on the anchors to t = 0.02 s (TL plate \
         1.4883·10⁹ → 1.2182·10⁹, UL-ENOG plate 5.4688·10⁹ → 4.8021·10⁹, twisting column \
         6.3873·10⁹ → 5.2575·10⁹) with the same results, but would not start on a CPU \
         without AVX2. The loops of `sph_core::parallel` now run each task's rows through \
         `sph_core::wide::dispatch`: a copy compiled with `#[target_feature(enable = \
         \"avx2,fma\")]` when the CPU has both (checked once), the per-particle closures \
         marked `#[inline(always)]` so that each copy holds the whole loop. That recovers \
         all of it (the table above, build 1ea9cfd against c602811: TL plate 1.1625·10⁹, \
         −21.9 %; UL-ENOG plate 4.8452·10⁹, −11.4 %; twisting column 5.2400·10⁹, −18.0 %; the MPS cantilever plate of the paragraph \
         above 6.404·10⁹ → 5.032·10⁹, −21.4 %). \
         The UL plate's loops by instructions at that build: the refresh of the pair data \
         (`PairSymmetry::fill`) 33 %, the force gather 24 %, the rate gather 19 %, the \
         neighbour search 6 %, the serial pair halves of each new list (`PairSymmetry::new`) \
         5 %. The same bits: Rust never fuses `a * b + c` on its own and LLVM \
         vectorises only where the order of the operations stays; the results files of 26 \
         scenes of all seven methods equal dataset by dataset against the previous build \
         (the 2D plate with all six methods, the twisting column, the bending column stored \
         and recomputed, the 3D plate, the UL-OAS, MPS rings, the Hertz impact, the pressurised \
         ring, slab, MPS and TL-HF cantilever plates, static cantilever, 2D ball–plate, and the \
         first steps of the punching and pulling strips, the stent and the 3D balls), and a test \
         runs five scenes of every method family with the copy on and off. Time, Intel Xeon \
         2026-12-03, the three binaries (old, new, a copy of the old) interleaved ten times: \
         wall time moved by ±20 % with the load of the host that day, but the user time of one \
         thread repeated to ±2 % (the copy of the old binary against the old: medians \
         0.995–1.000). One thread, user time (`/usr/bin/time`; `sph run oscillating-plate-2d \
         --method tl --set h_over_dp=1.3 --set end_time=0.25 --no-output --threads 1`, the \
         same with `--method ul-enog --set end_time=0.05`, and the twisting column's anchor \
         command with `--set end_time=0.05`; medians): TL plate to 0.25 s 2.85 → 2.52 s (−11 %, \
         ratios 0.88–0.90 without the two extremes each side), UL-ENOG plate to 0.05 s 2.71 → \
         2.62 s (−3 %, 0.93–1.02), twisting column to 0.05 s 4.14 → 4.01 s (−2.5 %, \
         0.96–0.98). So most instructions saved in the 3D loops are cheap ones (the register \
         copies of two-operand SSE code); the wall-time ratios to SPHinXsys are to be \
         measured again on a quiet machine. Symbol names now follow the v0 scheme \
         (`.cargo/config.toml`), so a profile names each loop's AVX2 copy after its closure \
         (`instructions` lists it as `… (AVX2)`).\n\n\
         **The per-step checks in one pass; square roots four at a time, dropped.** TL and \
         MPS checked their state after every step in two loops on the team (finite positions, \
         velocities and deformation gradients; then `det F > 0`), and MPS its accelerations in \
         a serial third. `diagnostics::check_state` does all of it in one loop on the team, \
         array by array with no branch (a NaN or infinity is an exponent of all ones), and \
         searches again only when something failed, to name the same entry as before \
         (tested). Instructions (`valgrind --tool=cachegrind --cache-sim=no`, one thread, the \
         command of the MPS paragraph above; build e28014b against acdcd21): MPS \
         cantilever plate to 0.02 s 5.032·10⁹ → 4.632·10⁹ (−8.0 %; the checks 549·10⁶ → \
         151·10⁶); the table above: TL plate 1.1625·10⁹ → 1.1112·10⁹ (−4.4 %), twisting \
         column 5.2400·10⁹ → 5.1891·10⁹ (−1.0 %), the UL plate unchanged (UL checks its state \
         once per advection step only); the same bits (results files of 16 scenes equal). \
         MPS's step criterion (`state_dt`: the largest `|v|` and `|a|`) now folds a maximum and \
         a NaN flag, which the compiler vectorises, instead of `max_or_nan` (the same values): \
         302·10⁶ → 207·10⁶ instructions, the cantilever plate 4.632·10⁹ → 4.537·10⁹ (−2.0 %; \
         build 5344937). \
         The refresh's square root and division were also taken eight pairs at a time \
         (separations gathered per component, the norms and `W′` of the group computed \
         without branches, so the compiler issued `vsqrtpd` on four pairs; the same bits), and \
         the disorder indicator's two square roots per pair likewise. On 2026-12-03 the host \
         made whole runs unusable for this (the same binary's user time varied by ±20 % between \
         runs and between the two cores at the same moment), so the two forms were timed in \
         one process, alternating every 50 refreshes over 200 rounds, on pairs of the \
         plate's size (1,612 particles) and the column's (6,100): the grouped refresh took \
         1.10–1.12× the time of the scalar one in 2D (medians of the per-round ratios of two \
         runs) and 1.50–1.53× in 3D; the grouped disorder indicator 1.35× in 2D and 0.99× in \
         3D. Moving the data into and out of the groups costs more than the square roots \
         save (the refresh is not bound by the divider alone); dropped, as the same idea on \
         the SSE2 build was before.\n\n\
         **The monitor's sample on the stepping thread.** `drive` takes the monitor's samples \
         between stretches of steps, and took them on the calling thread, while the steps run \
         on a worker of the pool (`steps_until`). By the time the calling thread woke up, the \
         team's helper had parked, and the first loops of the sample ran without it: in \
         `perf record -e cpu-clock` of the twisting column to t = 0.1 s on two threads (the \
         anchor command with `--set end_time=0.1 --threads 2`; 200 samples in 562 steps), the \
         calling thread did 11.6 % of all samples in the disorder indicator and the helper \
         4.2 %, and the helper spun 8.0 %. `steps_until` now takes the sample itself when its \
         steps end at a sample time, right after the last step on the same worker: 7.5 % on \
         the stepping threads and 8.4 % on the helper, which spun 3.7 %. The same samples \
         (results files of 16 scenes equal). In the full anchor run the monitor samples five \
         times less often per step, so this is worth about 1 % of its wall time on two \
         threads, more for shorter runs.\n\n\
         **The unmet rows beside SPHinXsys on a loaded host (2026-12-03).** SPHinXsys \
         9f33297 was built again as described below the anchor table (its outputs removed, \
         the TBB threads from an environment variable; the patch kept outside the repository) \
         and run interleaved with our build 5a46f7d, three rounds, whole-process wall time \
         (`/usr/bin/time`). The host was loaded that day (both programs ran about 1.8× slower \
         than on 2026-12-02 and the same binary's time varied by ±25 % between runs), so these \
         are not the table's figures, only a check of where the rows stand; ratio = SPHinXsys / \
         ours of the runs made one after the other: UL-ENOG plate, two threads: 38.6/19.8, \
         38.3/18.7, 44.4/22.3 s, ratios 1.95, 2.06, 1.99 (the table: 2.02); twisting column, \
         two threads: 19.9/7.7, 21.1/8.7, 19.1/6.5 s, ratios 2.59, 2.41, 2.93 (2.25); one \
         thread: 34.4/13.0, 42.6/13.7, 41.3/19.0 s, ratios 2.65, 3.10, 2.17 (2.44). The UL \
         plate on two threads stays at 2×; the column's rows are near or above 2.5× but within \
         the noise of that day.\n\n\
         **The UL plate's serial gaps on two threads (2026-12-03).** Per-thread profiles \
         (`perf record -e cpu-clock`, the UL-ENOG anchor command with `--set end_time=0.1 \
         --threads 2`; shares of all samples, stepping thread / helper) at the start: refresh \
         12.4 / 9.6 %, force gather 9.9 / 8.1 %, the helper spinning 8.8 %, the stepping \
         thread waiting in `run_tasks` 8.0 % and in `sched_yield` 5.4 %. The halves of each \
         new neighbour list (`PairSymmetry::new`, 3 % of the one-thread time, about 300 µs per \
         rebuild) ran on the stepping thread, long enough for the helper to park (its spin is \
         200 µs): counted in a throw-away build of the team, 654–839 parks and 1,724–2,162 \
         tasks taken over by the stepping thread per run (of about 34,000), because the woken \
         helper came late. `PairSymmetry::new` now builds its halves block by block on the \
         team (the blocks of `gather_blocks`, named by `parallel::blocks`; three passes per \
         block, the split into computed and copied slots without branches): 232–356 parks and \
         436–730 tasks taken over, `sched_yield` 0.1 %, waiting in `run_tasks` 3.3 %; timed \
         in one process against the old build of the whole list on pairs of the plate's size \
         and the column's, one thread: 0.93× and 0.50× the time. The stepping thread still \
         did more of each loop (refresh 12.4 / 9.8 %, force gather 11.1 / 9.3 %) and the \
         helper spun 13.7 %: \
         the energy budget's work of the step (`step_works`, five dot products per particle, \
         every acoustic step) was a serial loop on the stepping thread. It is now summed per \
         block on the \
         team, each block in particle order and the blocks in order, so the same bits for \
         every thread count (tested); the budget's sums of bodies of 1,024 particles or more \
         change at round-off (the plate's `shear_work_final` 0.6484969759539243 → \
         0.6484969759539246; every particle dataset of the 16 scenes equal). After both: the \
         two threads do equal shares of every loop (refresh 11.5 / 11.3 %, force gather \
         11.4 / 11.5 %, rate gather 7.8 / 7.8 %), the helper spins 8.2 % and the stepping \
         thread waits in `run_tasks` \
         5.1 %. Wall time to t = 0.1 s, the builds interleaved (host loaded, ±15 % between \
         runs): median ratio of the rounds 0.962 (14 rounds) for the halves, then 0.967 (12) \
         for the work sums. Beside SPHinXsys in one window (the full anchor run, two threads, \
         three rounds, each round SPHinXsys, the build before and the build after; the host \
         loaded again, SPHinXsys 29.5–43.4 s against 21.4 s quiet): SPHinXsys / ours 2.07, \
         1.68, 2.04 before and 2.18, 1.89, 2.40 after (ours 16.6 / 17.5 / 21.3 s → 15.8 / \
         15.6 / 18.1 s). The row stays below 2.5× on this host. The twisting column in the \
         same way with the build after (SPHinXsys 22.8–26.4 s on two threads and 43.5–45.1 s \
         on one, against 10.6 and 20.8 s quiet): two threads 22.85/10.39, 22.83/11.72, \
         26.41/9.70 s, ratios 2.20, 1.95, 2.72; one thread 43.49/15.55, 45.14/17.32, \
         44.38/14.56 s, ratios 2.80, 2.61, 3.05. On the loaded host the second thread helps \
         our run less than SPHinXsys's (our user time grows from 14–17 s to 18–20 s, theirs \
         stays at 42–45 s; the helper's spinning counts as user time, but why the loaded \
         host costs the team more than TBB's workers is not measured). A kernel form without the \
         refresh's division was also timed (storing `x_i − x_j` and `W′/r` in closed form: \
         0.77× the refresh's time in 2D, 0.90× in 3D, same process, alternating), but the \
         Riemann solver and the Laplacian need `e_ij` and `1/r` in the gathers, which would \
         then divide once per directed pair instead of once per unordered pair; not pursued. \
         One thread executes fewer instructions too (the table below, build f638f66 against \
         e28014b): UL-ENOG plate 4.8452·10⁹ → 4.6559·10⁹ (−3.9 %: the work sums now in the \
         AVX2 copy, the halves' build without the branchy transpose), TL plate and column \
         unchanged. The refresh then reloaded the kernel's constants and the positions' base \
         for every pair (the closure's captures, read through memory); copied into locals they \
         stay in registers, the same operations in the same order (16 scenes equal): UL-ENOG \
         plate 4.6559·10⁹ → 4.5320·10⁹ (−2.7 %, build 0bc9343; −6.5 % against e28014b). \
         Tasks of at least 256 particles instead of 512 (four blocks and six tasks \
         on the plate, so that a helper whose core the host takes away holds back less) were \
         timed the same way: UL plate two threads 0.949 (10 rounds) and then 1.027 (16 \
         rounds), column 0.89 (6 rounds, 0.78–1.21): inside the host's noise, not changed.\n\n\
         **Fewer loops per UL sub-step (2026-12-03, fifth session).** An acoustic sub-step of \
         UL-ENOG with refreshed kernel data was six loops on the team: the drift, the refresh \
         of the pair data, the force gather, the energy budget's work sums, the kick and the \
         rate gather. The refresh and the force gather are now one loop \
         (`PairSymmetry::fill_then`): each task fills its block of pairs and then sums the \
         forces of the block's rows, which read only their own pairs, complete once the block \
         is filled because mirrors are copied only within a block. The budget's work sums and \
         the kick are one pass too (`energy::kick_with_works`: each block kicks its particles \
         after taking its sum, so the sums keep their block order). Four loops per sub-step; \
         the results are the same bits (16 scenes, every dataset and every summary value). The \
         rebuild's scan of the pairs for coincident particles, 82 % of the rebuild's own \
         samples on the stepping thread while the helper waited, now runs on the team \
         (`parallel::first_index`). Per-thread profiles, the UL-ENOG anchor command with \
         `--set end_time=0.25 --threads 2`, the build before (0bc9343) and after (fc35c19) \
         alternated, two runs each, the host loaded: the helper spinning and the stepping \
         thread waiting together took 16.4 % and 15.3 % of the samples before, 12.5 % and \
         13.9 % after; the fused loop took 23.4 / 23.7 % and 23.6 / 22.4 % (stepping thread / \
         helper), against 11.2 + 11.5 / 10.3 + 10.9 % for the two loops before. Instructions, \
         one thread, to t = 0.02 s (cachegrind, whole process): 5.9301·10⁹ → 5.9455·10⁹ \
         (+0.26 %): the fused loop executes 1.4 % more than the refresh and the gather did \
         (the row slices of each block), the fused kick 15 % fewer than the sums and the kick. \
         Wall time to t = 0.1 s, two threads, the builds interleaved 30 rounds: median ratio \
         0.973 (0.75–1.27: the host's noise that day). The `cbrt` of `J^(−2/3)` (3D \
         Neo-Hookean stress) is 5 % of the twisting column's one-thread time: Rust links the \
         correctly rounded `cbrt` of its `compiler_builtins` (CORE-MATH), about 25 ns per call \
         here. A division-free replacement (Newton steps on `x^(−1/3)` and an exact rounding \
         test with FMA residuals, falling back to the library's `cbrt` when undecided; the \
         same bits on 2·10⁸ inputs, 13 fallbacks) was not faster (0.9–1.18× the library's \
         time, one process, alternating): not adopted. The monitor's disorder indicator is \
         another 5.4 % of the column's one-thread time (`perf record`, the anchor command; two \
         square roots and a kernel value per pair at each of the 200 samples). The anchor \
         rows were then timed beside SPHinXsys in the same rounds (`case-timings --sphinxsys`, \
         the table below the anchor table; build 741590d, the physics of c4aa48f), the host \
         loaded: SPHinXsys took 1.6–3.1× its quiet-window times. Median ratios of three \
         rounds: UL-ENOG plate 2.53 on one thread and 1.88 (1.85–2.37) on two; twisting \
         column 2.31 (2.25–2.74) on one thread and 2.76 (2.58–2.83) on two; TL plate 5.80 and \
         3.19. Our two-thread runs lost the most to the load (the TL plate took as long on two \
         threads as on one).\n\n\
         **The UL plate's two rows, and two rewrites that did not pay (2026-12-03, sixth \
         session).** SPHinXsys's UL test updates the kernel data with the neighbour list only, \
         once per advection step; ours recomputes them in every acoustic sub-step by default \
         (docs/methods.md). The anchor rows now include the UL plate with `--set \
         refresh_kernel_data=false`, SPHinXsys's scheme. Timed beside SPHinXsys in the same \
         rounds (build 256dee9, the physics of a9f62bf; the host loaded, SPHinXsys 1.7–1.9× \
         its quiet times), median of three rounds: the default UL plate 2.70 (2.60–2.88) on \
         one thread and 2.60 (2.08–2.77) on two; with the kernel data frozen 3.89 (3.29–3.96) \
         and 2.94 (2.69–3.02); the twisting column 2.39 (2.32–2.39) and 2.92 (2.41–3.04); the \
         TL plate 4.81 and 2.91. Per-thread profile of the default UL plate on two threads \
         (`perf record -e cpu-clock`, the anchor command to t = 0.25 s, build a9f62bf): the \
         fused refresh and force gather 25.7 / 24.9 % (stepping thread / helper), the rate \
         gather 8.8 / 8.5 %, the neighbour search 3.0 / 2.9 %, the helper spinning 6.0 %, the \
         stepping thread waiting 2.6 %, its own serial work (cell grid, list assembly, \
         permutation, the monitor's `hypot`, `atan2` and `sincos`) about 2.5 %. The twisting \
         column on one and two threads (to t = 0.1 s, 2,000 samples per second, alternated \
         twice): 11,330 and 10,780 samples on one thread, 11,195 and 12,031 on two, so the \
         second thread adds no work; what one thread lacks is in the loops themselves. Their \
         time per pair hardly depends on whether the pair data fit the cache (the column at \
         resolution 5, 10 and 16: 775, 6,100 and 24,832 particles, 1.4, 14 and 62 MB of pair \
         data; two runs each, 150 steps, the monitor off): HF acceleration 7.3–8.5, 6.7–7.8 \
         and 7.5–8.4 ns per pair, deformation rate 3.5–3.7, 4.2–4.9 and 4.7–5.1 ns (loaded \
         host, about twice the quiet times). Tried and dropped: (1) the disorder indicator's \
         two square roots per pair in one two-lane `vsqrtpd` (the same bits): its samples over \
         the HF acceleration's 0.40 and 0.42 before, 0.46 and 0.44 after (the column to t = \
         0.1 s, one thread, alternated), so the divider does not bound it; (2) fused \
         multiply-adds in the HF acceleration and the deformation rate (`mul_add` into the \
         accumulators; it changes the rounding): their samples over the stress update's grew \
         from 3.69 / 3.88 / 4.11 to 4.80 / 4.08 / 4.27 (three alternated runs), because each \
         pair then adds three dependent operations to the accumulator's chain instead of one; \
         the loops are not bound by the number of floating-point operations.\n\n\
         **The 3D TL pair loops with a vector in one register (2026-12-03, sixth session).** \
         The twisting column's one-thread row stayed below 2.5× in every measurement (2.44 in \
         the quiet window, 2.31 and 2.39 in the same rounds as SPHinXsys). Its two main loops, \
         the HF acceleration (49 % of the one-thread time) and the deformation rate (29 %), \
         were compiled from glam's `DVec3` and `DMat3` arithmetic into two-lane SSE plus scalar \
         operations with shuffles between them, about 40 instructions per pair for the HF \
         acceleration. `sph_tl::lanes` writes the 3D loops over stored pair data (the HF \
         acceleration, the stress divergence of plain TL and GM, the deformation rate) with a \
         vector, or a matrix column, in one AVX register whose fourth lane is zero (a masked \
         load, which never reads past the third component). Every lane does the glam code's \
         operations in the same order, without fused multiply-adds, so the results are the \
         same bits: a unit test compares each loop with the generic one, and the results files \
         of the 16 scenes and of six 3D TL scenes (the bending column with TL, TL-HF and TL-GM, \
         the pulling cylinder, the stent, the twisting column) are equal, every dataset and \
         every summary value. They run in the AVX2 copy of the loops; 2D, recomputed pair data \
         and the plain x86-64 copy keep the generic loops. Instructions, the twisting column to \
         t = 0.02 s (the table below, build db7fd51 against c4aa48f): 5.1894·10⁹ → \
         4.0730·10⁹ (−21.5 %), the HF acceleration 2.693·10⁹ → 1.833·10⁹ and the deformation \
         rate 1.389·10⁹ → 1.133·10⁹. Time, as samples of each loop over those of the stress \
         update (which did not change), the column to t = 0.1 s on one thread with the monitor \
         off, the two builds alternated three times: the HF acceleration 4.32 / 4.42 / 4.52 → \
         3.22 / 3.36 / 3.20, the deformation rate 2.69 / 2.68 / 2.61 → 2.25 / 2.50 / 2.28, the \
         whole run 8.66 / 8.79 / 8.78 → 7.09 / 7.53 / 7.14 (−17 %). Beside SPHinXsys in the same \
         rounds (build 294ce2d, the physics of db7fd51; the host less loaded than earlier that \
         day, SPHinXsys 1.2–1.5× its quiet times), median of three rounds: the twisting \
         column 3.34 (3.28–3.50) on one thread and 2.94 (2.74–3.10) on two; the TL plate 4.48 \
         and 2.92; the default UL plate 2.58 (2.49–2.80) and 2.00 (1.95–2.19); with the kernel \
         data frozen 3.89 (3.43–4.06) and 3.02 (2.89–3.13). So the UL plate's default row on \
         two threads is the one left below 2.5×.\n\n\
         **A second machine kind, and one more rewrite that did not pay (2026-12-03, seventh \
         session).** The session ran on an AMD EPYC of CPU family 26 (a virtual machine that \
         names its CPU only \"AMD EPYC\"), not the AMD EPYC of the team's record: SPHinXsys's TL \
         plate took 11.2 s on one thread there, against 21.3 s recorded. `sph_benchmarks::machine` \
         now adds the family and model to a CPU name without a generation, so the rows of this \
         machine stand beside SPHinXsys timed on it (built from 9f33297 as for the Intel rows). \
         In a quiet window (nothing else running; build c22b88d, the physics of db7fd51), median \
         of three: TL plate 2.53 / 1.45 s on one / two threads against SPHinXsys's 11.19 / \
         6.09 s (4.42 / 4.20×); UL-ENOG plate 11.73 / 6.55 s against 31.34 / 16.79 s (2.67 / \
         2.56×); with the kernel data frozen 8.60 / 4.76 s (3.64 / 3.53×); twisting column 4.25 \
         / 2.34 s against 18.30 / 8.29 s (4.31 / 3.55×). In the hour before, in rounds with \
         SPHinXsys (the same-rounds table), the medians were 4.61 / 4.37, 2.69 / 2.65, 3.72 / \
         3.41 and 4.72 / 3.78; three more rounds of the UL plate on two threads right after the \
         quiet window gave 2.29, 2.37 and 2.59 (ours 6.97–7.54 s, SPHinXsys 17.1–18.1 s). So on \
         this machine every anchor row is at or above 2.5×, the default UL plate on two threads \
         only just: its two-thread runs move by 10–20 % from one run to the next on this host \
         (`sph run oscillating-plate-2d --method ul-enog --set h_over_dp=1.3 --set \
         end_time=0.25 --no-output --threads N`, with and without `--set \
         refresh_kernel_data=false`, alternated, nothing else running: two threads, nine runs \
         each, refreshed 2.15–3.52 s and frozen 1.43–2.07 s; one thread, three runs each, \
         3.62–3.94 and 2.65–2.72 s; no steal time counted by the kernel). On one thread (`perf \
         record -e cpu-clock` of that command; shares of the samples, taken while a build ran \
         on the other core) the UL plate's fused refresh and force gather take 52 %, the rate \
         gather 19 %, the neighbour search 7 %, the pair halves of each new list 3 %, the \
         correction matrices of each rebuild 1.3 % plus 2.3 % in libm's `atan2`, `hypot` and \
         `sincos` (the 2×2 eigen-decomposition of the guarded inverse). Tried and dropped: the \
         refresh filled row by row, each row's computed slots, then its copies from their \
         mirrors (all in earlier rows of the block), then its force sum at once, so each \
         record is read back from the first-level cache instead of the second (the same bits: \
         4,187 datasets of nine UL scenes equal); the fused loop's samples over the rate \
         gather's went from 2.73 / 2.88 / 2.66 to 3.04 / 3.12 / 2.99 (`perf record` of the \
         command above on one thread, the builds alternated, nothing else running), and the \
         one-thread wall time did not move (3.42–3.75 s row by row, 3.54–3.85 s before; four \
         alternated runs each).\n\n\
         **The bending column's second thread, and a refresh without divisions (2026-12-03, \
         eighth session).** Same machine (AMD EPYC family 26). The criterion benches were run \
         there (`cargo bench -p sph-benchmarks --bench tl_step`, then `neighbor_search` and \
         `mps_step`; nothing else running), and each criterion mean now carries its machine (the \
         tables above). The 84,672-particle bending column goes from one thread to two 1.92× \
         (TL), 1.96× (TL-HF) and 1.93× (TL-GM); the old table of the earlier AMD EPYC had \
         TL-GM at 1.76×. Where the UL plate's fused loop spends its time on one thread (`perf \
         annotate` of the command of the paragraph above, nothing else running): the computed \
         pairs of the refresh 41 % of its samples, the copies to the mirrored slots 10 %, the \
         force sums 46 %; so the refresh is about 27 % of the one-thread run and the force \
         gather 24 %. The computed pairs spend their samples on the kernel polynomial right \
         after the square root and on the division `d/r`, so the loop was rebuilt without the \
         divider (a measurement build, not kept): `1/r` from an integer first guess and four \
         Newton steps, `r = r² · (1/r)` and `e = d · (1/r)` (round-off changes, the same step \
         counts). It was slower: one thread to t = 0.25 s, 3.32–3.67 s before and 4.13–4.47 s \
         without divisions (four alternated runs each). So the loop is not bound by the \
         divider's throughput: a longer chain of multiplications per pair costs more than the \
         division and square root it replaces. Nor did four pairs at a time help on this \
         machine (measurement builds, not kept): the four square roots and the divisions `d/r` \
         in AVX registers, the kernel polynomial per pair (the same bits), took 3.98–4.22 s \
         against 3.43–3.59 s; the same four pairs written lane by lane in plain Rust, which \
         LLVM did not vectorise (it kept the lanes on the stack and branched on `q ≥ 2`), \
         3.27–3.32 s against 3.19–3.29 s (three alternated runs each), as the AVX batches of \
         the paragraph on the refresh found on the Intel Xeon. Per-thread profile of the same \
         run on two threads (`perf record -e cpu-clock`, 1.998 s): the fused loop 24.5 / \
         22.9 % of the samples (stepping thread / helper), the rate gather 8.5 / 8.0 %, the \
         neighbour search 4.1 / 3.6 %, the helper spinning 8.4 % and the stepping thread \
         waiting 3.6 %, the stepping thread's work outside the parallel loops 4.3 % (the \
         largest pieces: the list's components and assembly 0.9 %, the cell grid 0.4 %, \
         libm's `atan2`, `sincos` and `hypot` 0.8 %). The memory, extreme-scene and impact rows \
         of the whole-run tables were timed on this machine too (`case-timings --only memory`, \
         then `extreme` and `impacts`, `--repeats 3`, nothing else running; same physics as \
         db7fd51): 3D TL-HF at 107,484 particles keeps 2.50 KiB per particle with stored pair \
         data and 0.84 KiB recomputed, the recomputed run taking 2.82× the stored one's time \
         (2.44× on the earlier AMD EPYC); system time is at most 3.2 % of user time on every \
         row.\n\n\
         **Between the loops.** A step is a handful of parallel loops of 10–50 µs. On the \
         rayon pool every loop woke a worker, which after the loop called `sched_yield` about \
         thirty times and then slept on a futex: the TL plate to t = 1 s on two threads made \
         337,277 `sched_yield` and 1,455 `futex` calls (`strace -f -c`), system time 21 % of \
         the user time. The loops of a step now run on `sph_core::team`, whose helpers spin in \
         user space for 200 µs between loops before they park (what OpenMP runtimes do with \
         an active wait policy), and so do the monitor's samples and MPS; set-up work (reference \
         pair data, sorted neighbour lists, MPS's WLS set-up) stays on rayon. Same run: 3,921 \
         `sched_yield` and 4,008 `futex` calls (around the monitor's 200 samples, measured \
         before the samples moved to the team), system time below 1.5 % of the user time on \
         every row above. The helper's spinning counts as user time, \
         so on two threads the user time is close to twice the wall time even while one thread \
         waits. Loops are cut \
         into equal tasks, a multiple of the thread count (three tasks of 537 particles on two \
         threads left one thread with two: 4 % slower). Same run, old and new build \
         interleaved, median of 4 (0.25 s simulated, quiet machine): TL 0.80 → 0.71 s, \
         UL-ENOG 2.94 → 2.85 s; to t = 1 s, UL-ENOG two threads, interleaved on the same \
         (slower) day: 13.8 s (13.76, 13.89) → 11.5 s (10.83, 12.19). Results are bit for bit \
         those of the rayon build (every dataset of the results files of five scenes).\n"
    )
    .unwrap();
}
