#!/usr/bin/env python3
"""Assert that h5py reads identical content from two sph-output results files.

Usage: h5py_check.py A.h5 B.h5   (exit 0 when identical, 1 otherwise)

Compares, with h5py, the root attributes, /meta and /summary attributes (names, dtypes,
values), every /snapshots/<n> (attributes time and step, dataset names, dtypes, shapes,
bit-identical values and the storage: chunks, compression and its level, shuffle) and every /probes/<name>/{time,position,velocity}. Also checks the
layout itself (the four top-level groups, the `json` attributes parse as JSON objects,
position is [n, 3]) so that two files both wrong in the same way do not pass.
"""
import json
import sys

import h5py
import numpy as np

failures = []


def fail(msg):
    failures.append(msg)


def norm_attr(v):
    """An attribute value as (kind, python value) so that str/bytes/numpy scalars compare."""
    if isinstance(v, bytes):
        return ("bytes", v)
    if isinstance(v, str):
        return ("str", v)
    a = np.asarray(v)
    return (a.dtype.str, a.tobytes(), a.shape)


def compare_attrs(where, a, b):
    ka, kb = sorted(a.attrs.keys()), sorted(b.attrs.keys())
    if ka != kb:
        fail(f"{where}: attribute names differ: {ka} vs {kb}")
        return
    for k in ka:
        va, vb = norm_attr(a.attrs[k]), norm_attr(b.attrs[k])
        if va != vb:
            fail(f"{where}: attribute {k!r} differs: {va!r} vs {vb!r}")


def compare_datasets(where, a, b):
    if not isinstance(a, h5py.Dataset) or not isinstance(b, h5py.Dataset):
        fail(f"{where}: not a dataset in both files")
        return
    if a.dtype != b.dtype or a.shape != b.shape:
        fail(f"{where}: {a.dtype}{a.shape} vs {b.dtype}{b.shape}")
        return
    if a[()].tobytes() != b[()].tobytes():
        fail(f"{where}: values differ")
    storage = lambda d: (d.chunks, d.compression, d.compression_opts, d.shuffle)
    if storage(a) != storage(b):
        fail(f"{where}: stored differently (chunks, compression, level, shuffle): {storage(a)} vs {storage(b)}")


def check_layout(name, f):
    for g in ("meta", "snapshots", "probes", "series", "summary"):
        if not isinstance(f.get(g), h5py.Group):
            fail(f"{name}: missing group /{g}")
            return False
    for g in ("meta", "summary"):
        if "json" in f[g].attrs:
            j = f[g].attrs["json"]
            j = j.decode() if isinstance(j, bytes) else j
            if not isinstance(json.loads(j), dict):
                fail(f"{name}: /{g} json is not an object")
    for s, grp in f["snapshots"].items():
        for a in ("time", "step"):
            if a not in grp.attrs:
                fail(f"{name}: /snapshots/{s} has no attribute {a}")
        if "position" in grp and (grp["position"].ndim != 2 or grp["position"].shape[1] != 3):
            fail(f"{name}: /snapshots/{s}/position is not [n, 3]")
    for p, grp in f["probes"].items():
        for d in ("time", "position", "velocity"):
            if d not in grp:
                fail(f"{name}: /probes/{p} has no {d}")
    for p, grp in f["series"].items():
        if "time" not in grp:
            fail(f"{name}: /series/{p} has no time")
        for d, ds in grp.items():
            if ds.shape != grp["time"].shape:
                fail(f"{name}: /series/{p}/{d} is not as long as its time")
    return True


def main(pa, pb):
    with h5py.File(pa, "r") as a, h5py.File(pb, "r") as b:
        if not (check_layout(pa, a) and check_layout(pb, b)):
            return
        compare_attrs("/", a, b)
        for g in ("meta", "summary"):
            compare_attrs(f"/{g}", a[g], b[g])
        for top in ("snapshots", "probes", "series"):
            na, nb = sorted(a[top].keys()), sorted(b[top].keys())
            if na != nb:
                fail(f"/{top}: members differ: {na} vs {nb}")
                continue
            for n in na:
                ga, gb = a[top][n], b[top][n]
                compare_attrs(f"/{top}/{n}", ga, gb)
                da, db = sorted(ga.keys()), sorted(gb.keys())
                if da != db:
                    fail(f"/{top}/{n}: datasets differ: {da} vs {db}")
                    continue
                for d in da:
                    compare_datasets(f"/{top}/{n}/{d}", ga[d], gb[d])
        print(
            f"h5py {h5py.__version__}: compared {len(a['snapshots'])} snapshots, "
            f"{len(a['probes'])} probes, {len(a['series'])} series, meta and summary"
        )


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    try:
        main(sys.argv[1], sys.argv[2])
    except Exception as e:  # unreadable file, missing object: a failure, not a crash
        fail(f"{type(e).__name__}: {e}")
    if failures:
        for f in failures:
            print("MISMATCH:", f)
        sys.exit(1)
    print("identical")
    sys.exit(0)
