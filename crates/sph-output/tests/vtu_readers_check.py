"""Reads the per-frame VTU files of sph-solids runs with meshio, VTK and PyVista (the .pvd
collection) and checks them against the HDF5 results read with h5py: frame count and times
(from the .pvd), points, vertex cells, and every per-particle field, value for value.

    python3 vtu_readers_check.py RUN.pvd [RUN.pvd ...]

Each reader that is not installed is skipped with a notice; h5py and numpy are required.
Exits non-zero on the first mismatch.
"""

import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np


def notice(msg):
    print(f"notice: {msg}")


def frames_of(pvd):
    root = ET.parse(pvd).getroot()
    assert root.get("type") == "Collection", f"{pvd}: not a collection"
    base = os.path.dirname(pvd)
    return [(float(d.get("timestep")), os.path.join(base, d.get("file")))
            for d in root.iter("DataSet")]


def snapshots_of(h5):
    with h5py.File(h5, "r") as f:
        snaps = []
        for name in sorted(f["snapshots"]):
            g = f["snapshots"][name]
            snaps.append((float(g.attrs["time"]),
                          {k: g[k][()] for k in g.keys()}))
        return snaps


def check_meshio(frames, snaps, pvd):
    try:
        import meshio
    except ImportError:
        notice("meshio not installed; its VTU check is skipped")
        return
    for (t, vtu), (ht, data) in zip(frames, snaps):
        m = meshio.read(vtu)
        n = data["position"].shape[0]
        assert np.array_equal(m.points, data["position"]), f"{vtu}: points"
        assert m.cells[0].type == "vertex" and len(m.cells[0].data) == n, f"{vtu}: cells"
        for k, v in data.items():
            if k == "position" or v.shape[0] != n:
                continue
            got = m.point_data[k]
            assert np.array_equal(got.reshape(v.shape), v), f"{vtu}: {k}"
    print(f"meshio: {pvd}: {len(frames)} frames, points and fields equal h5py's")


def check_vtk(frames, snaps, pvd):
    try:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        from vtkmodules.util.numpy_support import vtk_to_numpy
    except ImportError:
        notice("VTK not installed; its VTU check is skipped")
        return
    for (t, vtu), (ht, data) in zip(frames, snaps):
        r = vtkXMLUnstructuredGridReader()
        r.SetFileName(vtu)
        r.Update()
        g = r.GetOutput()
        n = data["position"].shape[0]
        assert g.GetNumberOfPoints() == n and g.GetNumberOfCells() == n, f"{vtu}: counts"
        assert np.array_equal(vtk_to_numpy(g.GetPoints().GetData()), data["position"]), vtu
        tv = g.GetFieldData().GetArray("TimeValue")
        assert tv is not None and tv.GetValue(0) == ht, f"{vtu}: TimeValue"
        pd = g.GetPointData()
        for k, v in data.items():
            if k == "position" or v.shape[0] != n:
                continue
            arr = pd.GetArray(k)
            assert arr is not None, f"{vtu}: no {k}"
            assert np.array_equal(vtk_to_numpy(arr).reshape(v.shape), v), f"{vtu}: {k}"
    print(f"VTK: {pvd}: {len(frames)} frames, points, times and fields equal h5py's")


def check_pyvista(frames, snaps, pvd):
    try:
        import pyvista
    except ImportError:
        notice("PyVista not installed; its .pvd check is skipped")
        return
    r = pyvista.get_reader(pvd)
    times = list(r.time_values)
    assert times == [t for t, _ in snaps], f"{pvd}: PyVista's times"
    for k in (0, len(times) - 1):
        r.set_active_time_point(k)
        m = r.read()[0]
        x = snaps[k][1]["position"]
        assert np.array_equal(np.asarray(m.points), x), f"{pvd}: PyVista frame {k}"
    print(f"PyVista: {pvd}: {len(times)} time values, first and last frames equal h5py's")


def main(paths):
    for pvd in paths:
        h5 = pvd[: -len(".pvd")] + ".h5"
        frames = frames_of(pvd)
        snaps = snapshots_of(h5)
        assert len(frames) == len(snaps), f"{pvd}: {len(frames)} frames, {len(snaps)} snapshots"
        for (t, _), (ht, _) in zip(frames, snaps):
            assert t == ht, f"{pvd}: time {t} vs {ht}"
        check_meshio(frames, snaps, pvd)
        check_vtk(frames, snaps, pvd)
        check_pyvista(frames, snaps, pvd)


if __name__ == "__main__":
    main(sys.argv[1:])
