"""Independent check of a per-rank XDMF file (crates/sph-cases/tests/results_files.rs).

Usage: python3 rank_xdmf_check.py FILE.xmf RANKS PARTICLES

Parses the XDMF with the standard XML parser (so it must be well formed) and, with h5py,
checks that every snapshot is a spatial collection of RANKS grids whose data items name
datasets of the stated dimensions in existing files, and that the grids' particle counts add
up to PARTICLES.
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py

path, ranks, particles = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
root = ET.parse(path).getroot()
folder = os.path.dirname(path)
temporal = root.find("Domain/Grid")
assert temporal.get("CollectionType") == "Temporal", temporal.attrib
snapshots = temporal.findall("Grid")
assert snapshots, "no snapshots"
files = {}
items = 0
for snap in snapshots:
    assert snap.get("CollectionType") == "Spatial", snap.attrib
    assert snap.find("Time") is not None, "a snapshot without its time"
    grids = snap.findall("Grid")
    assert len(grids) == ranks, (len(grids), ranks)
    total = 0
    for grid in grids:
        n = int(grid.find("Topology").get("NumberOfElements"))
        total += n
        for item in grid.iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            name, dataset = item.text.strip().split(":", 1)
            if name not in files:
                files[name] = h5py.File(os.path.join(folder, name), "r")
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            shape = files[name][dataset].shape
            assert shape == dims, (item.text, shape, dims)
            assert dims[0] == n, (item.text, dims, n)
            items += 1
    assert total == particles, (total, particles)
print(f"{path}: {len(snapshots)} snapshots of {ranks} grids, {items} data items resolved")
