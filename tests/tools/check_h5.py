"""Reads a peenflow impacts.h5 with h5py (the official HDF5 library) and compares every
impact record with impacts.csv, value for value, and checks that every contact point lies on
the specimen's surface (the plane z = 0, or the cylinder or the groove the root attributes
describe; the groove's surface is drawn here as a dense polyline from its dimensions),
and that /summary/jet_loading holds summary.json's jet_loading. Exit 0 and print 'ok N' on success."""
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
    assert shape in ("plane", "cylinder", "groove"), shape
    if shape == "groove":
        import math

        import numpy as np

        a = {k: float(f.attrs["specimen_" + k]) for k in
             ("radius_m", "bottom_m", "flank_deg", "depth_m", "edge_radius_m", "pitch_m", "axis_deg",
              "offset_m")}
        rf, hb, rho, depth = a["radius_m"], 0.5 * a["bottom_m"], a["edge_radius_m"], a["depth_m"]
        al = math.radians(a["flank_deg"])
        sa, ca = math.sin(al), math.cos(al)
        # Right half of the cross-section (s, z): bottom, fillet round (hb, rf), flank,
        # edge round its centre, land; mirrored, and repeated every pitch.
        f0 = (hb + rf * ca, rf * (1 - sa))
        f1 = (f0[0] + (depth - rho * (1 - sa) - f0[1]) * sa / ca, depth - rho * (1 - sa))
        ce = (f1[0] + rho * ca, f1[1] - rho * sa)
        sweep = math.pi / 2 - al
        n = 4000
        half = [(hb * k / n, 0.0) for k in range(n)]
        half += [(hb + rf * math.sin(sweep * k / n), rf - rf * math.cos(sweep * k / n)) for k in range(n)]
        half += [(f0[0] + (f1[0] - f0[0]) * k / n, f0[1] + (f1[1] - f0[1]) * k / n) for k in range(n)]
        half += [(ce[0] - rho * math.sin(sweep * (1 - k / n)), ce[1] + rho * math.cos(sweep * (1 - k / n)))
                 for k in range(n + 1)]
        pitch = a["pitch_m"]
        land_end = pitch / 2 if pitch > 0 else ce[0] + 0.5
        half += [(ce[0] + (land_end - ce[0]) * k / n, depth) for k in range(1, n + 1)]
        h = np.array(half)
        prof = np.concatenate([h[::-1] * [-1, 1], h[1:]])
        if pitch > 0:
            prof = np.concatenate([prof + [k * pitch, 0] for k in range(-1, 2)])
        p0, p1 = prof[:-1], prof[1:]
        seg = p1 - p0
        seg_len2 = (seg * seg).sum(axis=1)
        # (The pieces' joints appear twice: no zero-length segments.)
        keep = seg_len2 > 0
        p0, seg, seg_len2 = p0[keep], seg[keep], seg_len2[keep]
        phi = math.radians(a["axis_deg"])
        across = (math.sin(phi), -math.cos(phi))
        for k, (x, y, z) in enumerate(zip(f["impacts/x_m"][()], f["impacts/y_m"][()], f["impacts/z_m"][()])):
            q = np.array([x * across[0] + y * across[1] - a["offset_m"], z])
            if pitch > 0:
                q[0] -= round(q[0] / pitch) * pitch
            t = np.clip(((q - p0) * seg).sum(axis=1) / seg_len2, 0, 1)
            d = np.sqrt((((p0 + seg * t[:, None]) - q) ** 2).sum(axis=1)).min()
            assert d < 1e-9, f"impact {k} is {d} m off the groove"
    elif shape == "cylinder":
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
    # summary.json's jet loading, one attribute per field (when the run has one).
    import json
    loading = json.loads(f.attrs["summary_json"]).get("jet_loading")
    if loading is not None:
        got = f["summary/jet_loading"].attrs
        assert set(got.keys()) == set(loading.keys()), (sorted(got.keys()), sorted(loading))
        for key, want in loading.items():
            value = got[key]
            value = value.decode() if isinstance(value, bytes) else value
            assert value == want, f"jet_loading {key}: h5 {value!r} json {want!r}"
    else:
        assert "summary/jet_loading" not in f
    for name, ds in f["shots"].items():
        assert ds.attrs["units"] is not None
    nh = set(int(x) for x in f["never_hit/shot"][:])
    hit = set(int(r["shot"]) for r in rows)
    assert not (nh & hit), "a never-hit shot has impacts"
    assert len(nh) + len(hit) == len(f["shots/shot"]), "shots not accounted for"
print("ok", len(rows))
