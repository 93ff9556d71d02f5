"""Reads a peenflow impacts.h5 with h5py (the official HDF5 library) and compares every
impact record with impacts.csv, value for value, and checks that every contact point lies on
the specimen's surface (the plane z = 0, or the cylinder the root attributes describe).
Exit 0 and print 'ok N' on success."""
import csv
import sys

import h5py

h5_path, csv_path = sys.argv[1], sys.argv[2]
with open(csv_path, newline="") as f:
    rows = list(csv.DictReader(f))
with h5py.File(h5_path, "r") as f:
    for key in ("format", "tool", "tool_version", "seed", "scene", "title", "summary_json"):
        assert key in f.attrs, f"root attribute {key} missing"
    assert f.attrs["format"] == "peenflow-impacts/1"
    # The specimen's surface: every contact point lies on it.
    shape = f.attrs["specimen_shape"]
    shape = shape.decode() if isinstance(shape, bytes) else shape
    assert shape in ("plane", "cylinder"), shape
    if shape == "cylinder":
        import math
        rc = float(f.attrs["specimen_radius_m"])
        phi = math.radians(float(f.attrs["specimen_axis_deg"]))
        ax, ay = math.cos(phi), math.sin(phi)
        for k, (x, y, z) in enumerate(zip(f["impacts/x_m"][()], f["impacts/y_m"][()], f["impacts/z_m"][()])):
            along = x * ax + y * ay
            d = math.sqrt((x - along * ax) ** 2 + (y - along * ay) ** 2 + (z + rc) ** 2)
            assert abs(d - rc) < 1e-9 * rc, f"impact {k} is {d - rc} m off the cylinder"
    else:
        assert all(z == 0.0 for z in f["impacts/z_m"][()]), "an impact off the plane"
    g = f["impacts"]
    cols = list(rows[0].keys()) if rows else list(g.keys())
    assert set(cols) == set(g.keys()), (sorted(cols), sorted(g.keys()))
    for name in g.keys():
        ds = g[name]
        assert ds.attrs["units"], f"{name}: no units"
        assert len(ds) == len(rows), f"{name}: {len(ds)} rows in HDF5, {len(rows)} in CSV"
        values = ds[()]
        for k, row in enumerate(rows):
            want = float(row[name])
            got = float(values[k])
            assert got == want, f"{name}[{k}]: h5 {got!r} csv {want!r}"
    for grp in ("shots", "never_hit", "summary/normal_speed_histogram", "summary/radius_histogram"):
        assert grp in f, f"group {grp} missing"
    for name, ds in f["shots"].items():
        assert ds.attrs["units"] is not None
    nh = set(int(x) for x in f["never_hit/shot"][:])
    hit = set(int(r["shot"]) for r in rows)
    assert not (nh & hit), "a never-hit shot has impacts"
    assert len(nh) + len(hit) == len(f["shots/shot"]), "shots not accounted for"
print("ok", len(rows))
