#!/usr/bin/env bash
# CI step for sph-output: the post-processors' readers on real runs, and the second backend.
#
# Called from .ci/run (from the workspace root): `bash crates/sph-output/ci.sh`.
#
# 1. Installs what it can of the Python readers (each skipped with a notice when it cannot):
#    h5py and meshio (pip); with SPH_CI_VTK=1 also ParaView's Python (apt-get
#    `python3-paraview python3-h5py`, for Debian's /usr/bin/python3: VTK's XDMF 2 and XDMF 3
#    readers, those of ParaView's "XDMF Reader" and "Xdmf3 Reader S/T"), or, when apt cannot,
#    VTK's wheel (pip `vtk`: the XDMF 2 reader only).
# 2. Runs two short cases with the `sph` command (a TL plate on the default schedule, and a UL
#    ring collision, whose particles are reordered, with --compress and --format vtu) and
#    checks their `.xmf` with every reader available (tests/xdmf_readers_check.py: frame
#    count, times, points, cells, fields equal to h5py's) and their `.pvd` and `.vtu` frames
#    with meshio and VTK (tests/vtu_readers_check.py).
# 3. Installs libhdf5-dev (apt-get) and runs `cargo test -p sph-output --features hdf5-metno`
#    (with the h5py cross-check of both backends, plain and deflated). When the system library
#    cannot be installed it prints a notice and skips this part (the default, pure-Rust backend
#    is tested by the ordinary `cargo test` run).
# Test failures exit non-zero; a missing tool only skips what needs it, with a notice.
set -u

notice() { echo "notice: $*"; }

SUDO=""
CAN_APT=0
if command -v apt-get >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ]; then
        CAN_APT=1
    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        SUDO="sudo -n"
        CAN_APT=1
    fi
fi
APT_UPDATED=0
apt_install() {
    [ "$CAN_APT" = 1 ] || return 1
    export DEBIAN_FRONTEND=noninteractive
    if [ "$APT_UPDATED" = 0 ]; then
        $SUDO apt-get update -qq >/dev/null 2>&1 || true
        APT_UPDATED=1
    fi
    $SUDO apt-get install -y -qq "$@" >/dev/null 2>&1
}
pip_install() {
    python3 -m pip install -q "$@" >/dev/null 2>&1 \
        || python3 -m pip install -q --break-system-packages "$@" >/dev/null 2>&1
}
has_module() { "$1" -c "import $2" >/dev/null 2>&1; }

# --- 1. the Python readers ---------------------------------------------------------------
if command -v python3 >/dev/null 2>&1; then
    for module in h5py meshio; do
        has_module python3 "$module" || pip_install "$module" \
            || notice "pip install $module failed; what needs it is skipped"
    done
else
    notice "python3 not found; the h5py, meshio and VTK checks are skipped"
fi
DEB_PYTHON=/usr/bin/python3
# ParaView's Python and VTK's wheel are large downloads (hundreds of MB): installed only when
# asked for (SPH_CI_VTK=1), so CI stays within its time budget; the VTK readers are checked
# whenever they are present anyway.
if [ "${SPH_CI_VTK:-0}" = 1 ]; then
    if [ -x "$DEB_PYTHON" ] && ! { has_module "$DEB_PYTHON" vtkmodules.vtkIOXdmf3 \
        && has_module "$DEB_PYTHON" h5py; }; then
        echo "sph-output: installing ParaView's Python (python3-paraview) for its XDMF readers"
        apt_install python3-paraview python3-h5py \
            || notice "apt-get install python3-paraview python3-h5py failed or is not possible"
    fi
    if ! has_module "$DEB_PYTHON" vtkmodules.vtkIOXdmf2 && command -v python3 >/dev/null 2>&1 \
        && ! has_module python3 vtkmodules.vtkIOXdmf2; then
        pip_install vtk || notice "pip install vtk failed; VTK's XDMF reader is not checked"
    fi
else
    notice "VTK/ParaView readers are checked only if already installed (SPH_CI_VTK=1 installs them)"
fi

# --- 2. the readers on real runs ---------------------------------------------------------
runs_ok=1
interpreters=()
for py in python3 "$DEB_PYTHON"; do
    command -v "$py" >/dev/null 2>&1 && has_module "$py" "h5py, numpy" || continue
    # The same interpreter twice (python3 is /usr/bin/python3): once is enough.
    real=$("$py" -c "import sys; print(sys.executable)")
    case " ${interpreters[*]-} " in *" $real "*) continue ;; esac
    interpreters+=("$real")
done
if [ "${#interpreters[@]}" = 0 ]; then
    notice "no Python with h5py; the XDMF readers check on real runs is skipped"
else
    echo "sph-output: XDMF readers on real runs"
    dir=$(mktemp -d)
    sph() { cargo run --quiet -p sph-cases --bin sph -- "$@"; }
    sph run oscillating-plate-2d --method tl-hf --set resolution=4 --set end_time=0.02 \
        --out "$dir" --log-every 0 >/dev/null 2>"$dir/tl.log" \
        || { cat "$dir/tl.log"; runs_ok=0; }
    sph run colliding-rings-2d --method ul-enog --set end_time=0.0005 --compress \
        --out "$dir" --log-every 0 --format vtu >/dev/null 2>"$dir/ul.log" \
        || { cat "$dir/ul.log"; runs_ok=0; }
    for py in "${interpreters[@]}"; do
        [ "$runs_ok" = 1 ] || break
        echo "with $py:"
        "$py" crates/sph-output/tests/xdmf_readers_check.py "$dir"/*.xmf || runs_ok=0
        "$py" crates/sph-output/tests/vtu_readers_check.py "$dir"/*.pvd || runs_ok=0
    done
    rm -rf "$dir"
fi
[ "$runs_ok" = 1 ] || { echo "sph-output: XDMF readers check FAILED"; exit 1; }

# --- 3. the hdf5-metno backend -----------------------------------------------------------
have_hdf5() {
    pkg-config --exists hdf5 2>/dev/null && return 0
    [ -f /usr/include/hdf5/serial/hdf5.h ] || [ -f /usr/include/hdf5.h ]
}
if ! have_hdf5; then
    apt_install libhdf5-dev \
        || { notice "libhdf5-dev is missing and cannot be installed (sph-output hdf5-metno tests skipped)"; exit 0; }
    have_hdf5 \
        || { notice "libhdf5-dev installed but the HDF5 headers were not found (hdf5-metno tests skipped)"; exit 0; }
fi
echo "sph-output: testing the hdf5-metno backend"
exec cargo test -p sph-output --features hdf5-metno
