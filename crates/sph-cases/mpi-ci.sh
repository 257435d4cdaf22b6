#!/usr/bin/env bash
# CI step for distributed runs: `sph run` under `mpirun` (feature `mpi` of sph-cases).
#
# Called from .ci/run (from the workspace root): `bash crates/sph-cases/mpi-ci.sh`.
#
# Installs an MPI library with its headers and libclang (apt-get `libopenmpi-dev
# libclang-dev`, which rsmpi's build needs) when they are missing and it can; when it cannot,
# prints a notice and skips (the distributed code itself is tested by the ordinary
# `cargo test` run, on in-process ranks). Then runs `cargo test -p sph-cases --features mpi
# --test mpi` (after clippy with the feature): a TL-HF bending column and the MPS cantilever
# plate on 1, 2 and 3 ranks (oversubscribed on 2 cores), the results compared bit for bit; a
# 2-rank run checkpointed and resumed on 2 ranks; the refusals (UL, another rank count).
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
have_mpi() {
    command -v mpirun >/dev/null 2>&1 && command -v mpicc >/dev/null 2>&1 \
        && { [ -f /usr/lib/x86_64-linux-gnu/openmpi/include/mpi.h ] \
            || pkg-config --exists ompi 2>/dev/null || pkg-config --exists mpich 2>/dev/null \
            || mpicc -show >/dev/null 2>&1; } \
        && { ls /usr/lib/llvm-*/lib/libclang*.so* >/dev/null 2>&1 \
            || ls /usr/lib/x86_64-linux-gnu/libclang*.so* >/dev/null 2>&1; }
}
if ! have_mpi; then
    if [ "$CAN_APT" = 1 ]; then
        export DEBIAN_FRONTEND=noninteractive
        $SUDO apt-get update -qq >/dev/null 2>&1 || true
        $SUDO apt-get install -y -qq libopenmpi-dev openmpi-bin libclang-dev >/dev/null 2>&1 \
            || { notice "apt-get install libopenmpi-dev libclang-dev failed (MPI tests skipped)"; exit 0; }
    else
        notice "no MPI library and headers, and no apt-get as root (MPI tests skipped)"
        exit 0
    fi
    have_mpi || { notice "MPI installed but mpirun, mpicc or libclang not found (MPI tests skipped)"; exit 0; }
fi
echo "sph-cases: clippy with the mpi feature"
cargo clippy -p sph-cases --all-targets --features mpi -- -D warnings || exit 1
echo "sph-cases: sph run under mpirun on 1, 2 and 3 ranks"
# A rank waiting for a partner that never comes would hang CI: bounded (it takes seconds).
exec timeout 900 cargo test -p sph-cases --features mpi --test mpi
