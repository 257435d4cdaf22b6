#!/usr/bin/env bash
# Strong scaling of distributed TL-HF on the 84,672-particle bending column (resolution 24):
# 1 rank × 1 thread, 2 ranks × 1 thread (mpirun), and 1 rank × 2 threads beside them.
# Prints each run's wall and solver seconds from its summary, and checks that the three runs
# end with the same probe record (the distributed run is bit-identical to one process).
#
#   bash benchmarks/strong-scaling.sh            # builds `sph` with --features mpi (release)
#   SPH=path/to/sph bash benchmarks/strong-scaling.sh
#   SETS="--set resolution=24 --set end_time=0.2" bash benchmarks/strong-scaling.sh
#
# Run it on a quiet machine: the timings are the point. OpenMPI as root needs
# --allow-run-as-root; MPIRUN_FLAGS overrides the flags given to mpirun.
set -euo pipefail
cd "$(dirname "$0")/.."
SETS=${SETS:-"--set resolution=24"}
MPIRUN_FLAGS=${MPIRUN_FLAGS:-"--allow-run-as-root --oversubscribe --bind-to none"}
if [ -z "${SPH:-}" ]; then
    cargo build --release -p sph-cases --features mpi --quiet
    SPH="${CARGO_TARGET_DIR:-target}/release/sph"
fi
dir=$(mktemp -d)
run() { # label, threads, then the command that starts sph
    local label=$1 threads=$2
    shift 2
    # shellcheck disable=SC2086
    "$@" run bending-column-3d --method tl-hf $SETS --threads "$threads" --no-output \
        --log-every 0 --summary "$dir/$label.json" >/dev/null
    python3 - "$dir/$label.json" "$label" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]:<22} particles {s['particles']:>7}  steps {s['steps']:>6}  "
      f"wall {s['wall_seconds']:8.2f} s  solver {s['solver_seconds']:8.2f} s  "
      f"s_x_max {s['s_x_max']!r}")
PY
}
# shellcheck disable=SC2086
{
    run 1rank-1thread 1 "$SPH"
    run 2ranks-1thread 1 mpirun $MPIRUN_FLAGS -n 2 "$SPH"
    run 1rank-2threads 2 "$SPH"
}
rm -rf "$dir"
