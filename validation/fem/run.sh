#!/usr/bin/env bash
# Finite-element references (validation/fem/README.md): the punching and pulling strips and the
# oscillating plate's small-amplitude period. Installs the pinned Python tools (setup.sh), then
# runs the three scripts under `nice`, writing validation/results/fem-punching.json,
# validation/results/fem-pulling.json and validation/results/fem-plate-modes.json.
# Optional tool: without Python or the packages it prints a notice and exits 0.
# Extra arguments (e.g. --quick) are passed to every script.
set -u
HERE="$(cd "$(dirname "$0")" && pwd)"
PY="${PYTHON:-python3}"
bash "$HERE/setup.sh"
if ! "$PY" -c "import numpy, scipy, skfem" >/dev/null 2>&1; then
    echo "notice: numpy/scipy/scikit-fem unavailable; FEM reference skipped"
    exit 0
fi
set -e
cd "$HERE/../.."
start=$(date +%s)
nice -n 10 "$PY" validation/fem/pulling.py "$@"
nice -n 10 "$PY" validation/fem/punching.py "$@"
nice -n 10 "$PY" validation/fem/plate_modes.py "$@"
echo "fem reference: done in $(( $(date +%s) - start )) s"
