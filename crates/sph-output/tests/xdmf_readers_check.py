#!/usr/bin/env python3
"""Read sph-output XDMF sidecars with the post-processors' readers and compare with h5py.

Usage: xdmf_readers_check.py RUN.xmf [RUN2.xmf ...]
Exit status: 0 when every available reader agrees with h5py on every file, 1 on a mismatch,
2 on bad usage.

What h5py reads from the `.h5` beside each `.xmf` is the reference: the frames are the
snapshots that have a `position` dataset, in name order; a frame's fields are its datasets
whose first dimension is the particle count n (`position` included).

Readers, each used when it can be imported in this interpreter (a notice names the others):

* meshio (`meshio.xdmf.TimeSeriesReader`): the frame count, each frame's time (exactly),
  the points (= frame 0's `position`), one `vertex` cell block whose connectivity is a
  permutation of 0..n, and each frame's point data: the same names, shapes and bit-identical
  values as h5py (integer ids as equal integers);
* VTK's XDMF 2 reader (`vtkXdmfReader`, ParaView's "XDMF Reader"; from `pip install vtk` or
  ParaView's Python) and VTK's XDMF 3 reader (`vtkXdmf3Reader`, behind ParaView's "Xdmf3
  Reader S/T"; in ParaView's Python, not in the pip wheel): the time steps, and at each one
  an unstructured grid of n points equal to `position`, n one-point vertex cells covering every
  point, and one point array per field with the field's component count and values.

Prints one line per file and reader checked.
"""
import os
import sys

failures = []


def fail(msg):
    failures.append(msg)


try:
    import h5py
    import numpy as np
except ImportError as e:  # the caller checks for h5py first; this is for a direct call
    print(f"notice: {e}; XDMF readers check skipped")
    sys.exit(0)


def expected_frames(xmf):
    """[(name, time, n, {field: array})] from the .h5 beside `xmf`, via h5py."""
    h5 = os.path.splitext(xmf)[0] + ".h5"
    frames = []
    with h5py.File(h5, "r") as f:
        for name in sorted(f["snapshots"].keys()):
            g = f["snapshots"][name]
            if "position" not in g:
                continue
            n = g["position"].shape[0]
            fields = {d: g[d][()] for d in g if g[d].ndim >= 1 and g[d].shape[0] == n}
            frames.append((name, float(g.attrs["time"]), n, fields))
    return frames


def same_values(got, want):
    """Bit-identical floats (NaN, -0.0 and sub-normals included), equal integers."""
    got = np.asarray(got)
    if want.dtype.kind == "f":
        got = got.astype(want.dtype, copy=False).reshape(want.shape)
        return got.tobytes() == want.tobytes()
    return got.size == want.size and np.array_equal(got.astype(np.int64).ravel(), want.astype(np.int64).ravel())


def is_permutation(ids, n):
    ids = np.asarray(ids).astype(np.int64).ravel()
    return ids.size == n and np.array_equal(np.sort(ids), np.arange(n))


def check_meshio(xmf, frames):
    import meshio

    where = f"meshio {meshio.__version__}: {xmf}"
    with meshio.xdmf.TimeSeriesReader(xmf) as r:
        if r.num_steps != len(frames):
            fail(f"{where}: {r.num_steps} frames, h5py has {len(frames)}")
            return
        points, cells = r.read_points_cells()
        n0 = frames[0][2]
        if not same_values(points, frames[0][3]["position"]):
            fail(f"{where}: points differ from the first snapshot's position")
        if [c.type for c in cells] != ["vertex"] or not is_permutation(cells[0].data, n0):
            fail(f"{where}: cells are not {n0} vertices covering every point: {cells}")
        for k, (name, t, n, fields) in enumerate(frames):
            time, point_data, _ = r.read_data(k)
            if time != t:
                fail(f"{where}: frame {k} time {time!r}, h5py {t!r}")
            if sorted(point_data) != sorted(fields):
                fail(f"{where}: frame {k} fields {sorted(point_data)}, h5py {sorted(fields)}")
                continue
            for d, want in fields.items():
                got = point_data[d]
                if got.shape != want.shape or not same_values(got, want):
                    fail(f"{where}: /snapshots/{name}/{d}: {got.dtype}{got.shape} differs from h5py's {want.dtype}{want.shape}")
    return f"{where}: {len(frames)} frames, times, points, cells and fields as h5py reads them"


def check_vtk(label, reader, xmf, frames):
    # numpy_support, not dataset_adapter: the latter shows 9-component arrays as transposed
    # 3x3 matrices; the values themselves are stored in the file's (row-major) order.
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as sddp
    from vtkmodules.vtkCommonCore import vtkVersion

    where = f"{label} (VTK {vtkVersion.GetVTKVersion()}): {xmf}"
    # Absolute: VTK's XDMF 3 reader resolves the .h5 wrongly from a bare relative file name.
    reader.SetFileName(os.path.abspath(xmf))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(sddp.TIME_STEPS()) or ()
    want_times = [t for _, t, _, _ in frames]
    if list(times) != want_times:
        fail(f"{where}: time steps {list(times)}, h5py {want_times}")
        return
    for (name, t, n, fields), step in zip(frames, times):
        reader.UpdateTimeStep(step)
        out = reader.GetOutputDataObject(0)
        if out.IsA("vtkMultiBlockDataSet") or out.IsA("vtkDataObjectTree"):
            it = out.NewIterator()
            it.InitTraversal()
            out = it.GetCurrentDataObject()
        if out is None or not out.IsA("vtkUnstructuredGrid"):
            fail(f"{where}: {name}: not an unstructured grid: {out and out.GetClassName()}")
            continue
        if out.GetNumberOfPoints() != n or out.GetNumberOfCells() != n:
            fail(f"{where}: {name}: {out.GetNumberOfPoints()} points, {out.GetNumberOfCells()} cells, want {n} each")
            continue
        conn = vtk_to_numpy(out.GetCells().GetConnectivityArray())
        sizes = {out.GetCell(c).GetNumberOfPoints() for c in range(n)}
        if sizes != {1} or not is_permutation(conn, n):
            fail(f"{where}: {name}: cells are not one vertex per particle")
        if not same_values(vtk_to_numpy(out.GetPoints().GetData()), fields["position"]):
            fail(f"{where}: {name}: points differ from position")
        for d, want in fields.items():
            arr = out.GetPointData().GetArray(d)
            if arr is None:
                fail(f"{where}: {name}: no point array {d!r}")
                continue
            comps = int(np.prod(want.shape[1:], dtype=np.int64))
            got = vtk_to_numpy(arr)
            if want.dtype.kind == "u":
                # Declared Int 8 (VTK has no unsigned 64-bit XDMF type): exact below 2^63,
                # saturated by the HDF5 library's conversion above.
                want = np.minimum(want, np.uint64(2**63 - 1))
            if arr.GetNumberOfComponents() != comps or arr.GetNumberOfTuples() != n or not same_values(got, want):
                fail(f"{where}: {name}/{d}: {arr.GetClassName()} {arr.GetNumberOfTuples()}x{arr.GetNumberOfComponents()} differs from h5py's {want.dtype}{want.shape}")
    return f"{where}: {len(frames)} time steps, points, vertex cells and point arrays as h5py reads them"


def main(paths):
    readers = []
    try:
        import meshio  # noqa: F401

        readers.append(("meshio", check_meshio))
    except ImportError:
        print("notice: meshio not available in this Python; meshio check skipped")
    try:
        from vtkmodules.vtkIOXdmf2 import vtkXdmfReader

        readers.append(("vtkXdmfReader", lambda x, f: check_vtk("vtkXdmfReader", vtkXdmfReader(), x, f)))
    except ImportError:
        print("notice: VTK's XDMF 2 reader (vtkmodules.vtkIOXdmf2) not available; skipped")
    try:
        from vtkmodules.vtkIOXdmf3 import vtkXdmf3Reader

        readers.append(("vtkXdmf3Reader", lambda x, f: check_vtk("vtkXdmf3Reader", vtkXdmf3Reader(), x, f)))
    except ImportError:
        print("notice: VTK's XDMF 3 reader (vtkmodules.vtkIOXdmf3, ParaView's Python) not available; skipped")
    for xmf in paths:
        frames = expected_frames(xmf)
        if not frames:
            fail(f"{xmf}: no snapshot with a position")
            continue
        for name, check in readers:
            before = len(failures)
            try:
                ok = check(xmf, frames)
            except Exception as e:  # a reader that throws: a failure, not a crash
                fail(f"{name}: {xmf}: {type(e).__name__}: {e}")
                continue
            if len(failures) == before:
                print(ok)
    print("readers checked: " + (", ".join(n for n, _ in readers) or "none"))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1:])
    if failures:
        for f in failures:
            print("MISMATCH:", f)
        sys.exit(1)
    sys.exit(0)
