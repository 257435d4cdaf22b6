#!/usr/bin/env bash
# Installs the pinned Python tools of the finite-element reference (validation/fem).
# Optional tool: when it cannot be installed, print a notice and exit 0 (project rule).
set -u
PY="${PYTHON:-python3}"
PINS="numpy==2.2.6 scipy==1.15.3 scikit-fem==12.0.1"

have() {
    "$PY" - <<'PYEOF' 2>/dev/null
import numpy, scipy, skfem
assert numpy.__version__ == "2.2.6" and scipy.__version__ == "1.15.3"
from importlib.metadata import version
assert version("scikit-fem") == "12.0.1"
PYEOF
}

if ! command -v "$PY" >/dev/null 2>&1; then
    echo "notice: $PY not found; the FEM reference is skipped"
    exit 0
fi
if have; then
    echo "fem setup: pinned tools already installed ($PINS)"
    exit 0
fi
# shellcheck disable=SC2086
if "$PY" -m pip install -q $PINS 2>/dev/null || "$PY" -m pip install -q --break-system-packages $PINS; then
    if have; then
        echo "fem setup: installed $PINS"
        exit 0
    fi
fi
echo "notice: could not install $PINS with pip; the FEM reference is skipped"
exit 0
