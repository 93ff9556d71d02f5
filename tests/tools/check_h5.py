"""Reads a peenflow impacts.h5 with h5py (the official HDF5 library) and compares every
impact record with impacts.csv, value for value. Exit 0 and print 'ok N' on success."""
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
