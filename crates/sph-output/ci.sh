#!/usr/bin/env bash
# CI step for sph-output's second backend (cargo feature `hdf5-metno`, the HDF5 C library).
#
# Called from .ci/run (from the workspace root): `bash crates/sph-output/ci.sh`.
# Installs libhdf5-dev (apt-get, with sudo when not root and sudo is available) and h5py
# (pip, for the cross-check test) when missing, then runs
#   cargo test -p sph-output --features hdf5-metno
# When the system library cannot be installed it prints a notice and exits 0 (the default,
# pure-Rust backend is tested by the ordinary `cargo test` run). A missing h5py only skips
# the h5py cross-check (the test prints its own notice). Test failures exit non-zero.
set -u

notice() { echo "notice: $* (sph-output hdf5-metno tests skipped)"; exit 0; }

have_hdf5() {
    pkg-config --exists hdf5 2>/dev/null && return 0
    [ -f /usr/include/hdf5/serial/hdf5.h ] || [ -f /usr/include/hdf5.h ]
}

if ! have_hdf5; then
    SUDO=""
    if [ "$(id -u)" != 0 ]; then
        if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
            SUDO="sudo -n"
        else
            notice "libhdf5-dev is missing and neither root nor passwordless sudo is available"
        fi
    fi
    command -v apt-get >/dev/null 2>&1 || notice "libhdf5-dev is missing and apt-get is not available"
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq >/dev/null 2>&1 || true
    $SUDO apt-get install -y -qq libhdf5-dev >/dev/null 2>&1 \
        || notice "apt-get install libhdf5-dev failed"
    have_hdf5 || notice "libhdf5-dev installed but the HDF5 headers were not found"
fi

if command -v python3 >/dev/null 2>&1 && ! python3 -c "import h5py" >/dev/null 2>&1; then
    { python3 -m pip install -q h5py >/dev/null 2>&1 \
        || python3 -m pip install -q --break-system-packages h5py >/dev/null 2>&1; } \
        || echo "notice: pip install h5py failed; the h5py cross-check will be skipped"
fi

echo "sph-output: testing the hdf5-metno backend"
exec cargo test -p sph-output --features hdf5-metno
