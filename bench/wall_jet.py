#!/usr/bin/env python3
"""What the wall jet changes: where and how fast the shots of the default scene land with
the free jet, with the stagnation layer alone, and with the layer and its wall jet
(`[jet] stagnation_layer_mm`, `wall_jet`; docs/model.md, "The air and the part").

usage: python3 bench/wall_jet.py [--bin PATH] [--seeds N] [--layer MM] [--figures DIR]
       (about 20 s for 48 seeds; needs the release binary, `cargo build --release`)

The scene is `peenflow init`'s (the paper's: 30 shots of 0.8 mm steel through the 6 mm
bore at 0.6 MPa, 100 mm onto the plate, shot-shot contacts, rebounds), and the same with
30 glass beads of 0.2 mm, a fine medium that the air moves more. Shots collide in
flight, so single runs are chaotic: the script runs each variant over the same seeds and
compares the distributions (means with their standard errors, median and 90th
percentile of the distance from the jet's axis), for the first impact of every shot and
for the later ones (rebounds that came back down).

With --figures DIR it only runs 300 glass beads (seed 1) in the free jet and with the
layer and its wall jet, and copies the two runs' impact maps to
DIR/impacts_glass_free_jet.png and DIR/impacts_glass_wall_jet.png (docs/figures).
"""
import argparse
import csv
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "peenflow")
GLASS = ('\n[materials.glass]\nyoungs_modulus_gpa = 63.0\npoisson_ratio = 0.22\n'
         'density_kg_m3 = 2500.0\n')


def scene_text(binary, tmp):
    path = os.path.join(tmp, "default.toml")
    subprocess.run([binary, "init", path], check=True, capture_output=True)
    return open(path).read()


def medium(text, name):
    if name == "steel":
        return text
    text = text.replace("diameter_mm = 0.8", "diameter_mm = 0.2", 1)
    text = text.replace('material = "table2-steel"  # E = 210', 'material = "glass"  # E = 210', 1)
    assert 'material = "glass"' in text, "the default scene's shot material line moved"
    return text + GLASS


def run(binary, tmp, text, seed, jet_keys, rows=True):
    """Runs the scene with `seed` and the `jet_keys` lines added to [jet]: its impacts'
    rows, or (`rows` false) its output directory."""
    text = text.replace("seed = 1 ", f"seed = {seed} ", 1).replace("[jet]\n", "[jet]\n" + jet_keys, 1)
    path = os.path.join(tmp, "scene.toml")
    open(path, "w").write(text)
    out = os.path.join(tmp, "out")
    subprocess.run([binary, "run", path, "--out", out, "-q", "--force"], check=True)
    if not rows:
        return out
    with open(os.path.join(out, "impacts.csv")) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def summary(rows):
    if not rows:
        return "| 0 | | | | |"
    r = sorted(math.hypot(float(x["x_m"]), float(x["y_m"])) * 1e3 for x in rows)
    vn = [float(x["normal_speed_m_s"]) for x in rows]
    vt = [float(x["tangential_speed_m_s"]) for x in rows]
    se = lambda v: statistics.stdev(v) / math.sqrt(len(v)) if len(v) > 1 else 0.0
    p90 = r[min(len(r) - 1, int(0.9 * len(r)))]
    return (f"| {len(rows)} | {statistics.mean(vn):.2f} ± {se(vn):.2f} | "
            f"{statistics.mean(vt):.2f} ± {se(vt):.2f} | {statistics.median(r):.2f} | {p90:.2f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--bin", default=BIN)
    p.add_argument("--seeds", type=int, default=48)
    p.add_argument("--layer", type=float, default=14.0, help="the layer's thickness, mm")
    p.add_argument("--figures", help="write the two glass-bead impact maps to this directory")
    a = p.parse_args()
    if not os.path.exists(a.bin):
        sys.exit(f"{a.bin} not found: build it with `cargo build --release`")
    variants = [
        ("free jet", ""),
        (f"layer {a.layer:g} mm", f"stagnation_layer_mm = {a.layer}\n"),
        (f"layer {a.layer:g} mm + wall jet", f"stagnation_layer_mm = {a.layer}\nwall_jet = true\n"),
    ]
    with tempfile.TemporaryDirectory() as tmp:
        base = scene_text(a.bin, tmp)
        if a.figures:
            glass = medium(base, "glass").replace("count = 30", "count = 300", 1)
            title = 'title = "paper Table 2: 30 shots, 0.8 mm, 0.6 MPa"'
            assert title in glass, "the default scene's title moved"
            for fig, what, keys in [("free_jet", "free jet", ""), ("wall_jet",
                                    f"{a.layer:g} mm layer and wall jet", variants[2][1])]:
                text = glass.replace(title, f'title = "300 glass beads of 0.2 mm, {what}"')
                out = run(a.bin, tmp, text, 1, keys, rows=False)
                dest = os.path.join(a.figures, f"impacts_glass_{fig}.png")
                shutil.copy(os.path.join(out, "impacts.png"), dest)
                print(f"wrote {dest}")
            return
        for name in ("steel", "glass"):
            text = medium(base, name)
            label = "steel 0.8 mm" if name == "steel" else "glass 0.2 mm"
            print(f"\n{label}, {a.seeds} seeds of `peenflow init`'s scene\n")
            print("| air | impacts | normal speed m/s | tangential speed m/s | "
                  "median r mm | 90 % r mm |")
            print("|---|---|---|---|---|---|")
            for vname, keys in variants:
                rows = [x for s in range(1, a.seeds + 1) for x in run(a.bin, tmp, text, s, keys)]
                first = [x for x in rows if x["first_hit"] in ("1", "true")]
                later = [x for x in rows if x["first_hit"] not in ("1", "true")]
                print(f"| {vname}, first impacts {summary(first)}")
                print(f"| {vname}, later impacts {summary(later)}")


if __name__ == "__main__":
    main()
