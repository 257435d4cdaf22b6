#!/usr/bin/env bash
# Finite-element reference of the punching and pulling strips (validation/fem/README.md).
# Installs the pinned Python tools (setup.sh), then runs both scripts under `nice`, writing
# validation/results/fem-punching.json and validation/results/fem-pulling.json.
# Optional tool: without Python or the packages it prints a notice and exits 0.
# Extra arguments (e.g. --quick) are passed to both scripts.
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
echo "fem reference: done in $(( $(date +%s) - start )) s"
