#!/usr/bin/env python3
"""What the stagnation layer changes over a bar: where and how fast the shots of
examples/spring_wire.toml land with the free jet and with layers over the wire
(`[jet] stagnation_layer_mm` with `[specimen] shape = "cylinder"`; docs/model.md, "The
air and the part").

usage: python3 bench/bar_layer.py [--bin PATH] [--seeds N] [--layers MM,MM,...] [--glass]
       (about 30 s for 24 seeds, 90 s with --glass; needs the release binary,
       `cargo build --release`)

The scene is the example's: S230 cast steel shot at 1.5 kg/min for 30 ms through the
paper's nozzle onto a wire of 4 mm radius, 100 mm below the exit; with --glass, glass
beads of 0.2 mm at 0.05 kg/min instead (a fine medium that the air moves more). Its shots collide in
flight, so single runs are chaotic: the script runs each variant over the same seeds and
compares the distributions of the first impact of every shot that hits (means with their
standard errors; the impacts' angle round the wire from its crest, median and 90th
percentile) and the share of the shots fed that hit the wire at all.
"""
import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "peenflow")
SCENE = os.path.join(ROOT, "examples", "spring_wire.toml")
RADIUS_MM = 4.0
SIEVE = '[shots.size_distribution]\ntype = "sieve"\ngrade = "S230"\n'
GLASS = ('[shots]\ndiameter_mm = 0.2\nmaterial = "glass"\n\n[materials.glass]\n'
         'youngs_modulus_gpa = 63.0\npoisson_ratio = 0.22\ndensity_kg_m3 = 2500.0\n')


def run(binary, tmp, seed, layer_mm, glass):
    """First impacts of every shot (rows of impacts.csv) and the number of shots fed."""
    text = open(SCENE).read()
    if glass:
        assert SIEVE in text and "mass_flow_kg_min = 1.5" in text, "the example's shots moved"
        text = text.replace(SIEVE, GLASS).replace("mass_flow_kg_min = 1.5", "mass_flow_kg_min = 0.05")
    assert not re.search(r"(?m)^\[jet\]", text), "the example grew a [jet] table: add the key to it"
    text = f"seed = {seed}\n" + text
    if layer_mm > 0:
        text += f"\n[jet]\nstagnation_layer_mm = {layer_mm}\n"
    path = os.path.join(tmp, "scene.toml")
    open(path, "w").write(text)
    out = os.path.join(tmp, "out")
    subprocess.run([binary, "run", path, "--out", out, "-q", "--force"], check=True)
    with open(os.path.join(out, "impacts.csv")) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    first = [r for r in rows if r["first_hit"] == "1"]
    with open(os.path.join(out, "shots.csv")) as f:
        fed = sum(1 for line in f if not line.startswith("#")) - 1
    return first, fed


def table_row(name, rows, fed):
    vn = [float(x["normal_speed_m_s"]) for x in rows]
    vt = [float(x["tangential_speed_m_s"]) for x in rows]
    # The angle round the wire from its crest (the wire's axis along y through (0, 0, -R)).
    ang = sorted(abs(math.degrees(math.atan2(float(x["x_m"]) * 1e3,
                                             float(x["z_m"]) * 1e3 + RADIUS_MM)))
                 for x in rows)
    se = lambda v: statistics.stdev(v) / math.sqrt(len(v))
    p90 = ang[min(len(ang) - 1, int(0.9 * len(ang)))]
    return (f"| {name} | {len(rows)} ({100 * len(rows) / fed:.1f} %) | "
            f"{statistics.mean(vn):.2f} ± {se(vn):.2f} | {statistics.mean(vt):.2f} ± {se(vt):.2f} | "
            f"{statistics.median(ang):.1f} | {p90:.1f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--bin", default=BIN)
    p.add_argument("--seeds", type=int, default=24)
    p.add_argument("--layers", default="0,2,4",
                   help="layer thicknesses, mm (0: the free jet; at most the wire's 4 mm)")
    p.add_argument("--glass", action="store_true", help="glass beads of 0.2 mm instead of S230")
    a = p.parse_args()
    layers = [float(v) for v in a.layers.split(",")]
    medium = "glass beads of 0.2 mm at 0.05 kg/min" if a.glass else "S230"
    print(f"examples/spring_wire.toml ({medium}) over seeds 1-{a.seeds}: first impacts of the shots that hit")
    print("| air | first impacts (of the shots fed) | normal speed m/s | tangential speed m/s "
          "| median angle from the crest, deg | 90 % angle, deg |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for layer in layers:
            rows, fed = [], 0
            for seed in range(1, a.seeds + 1):
                r, n = run(a.bin, tmp, seed, layer, a.glass)
                rows += r
                fed += n
            name = "free jet" if layer == 0 else f"layer {layer:g} mm"
            print(table_row(name, rows, fed), flush=True)


if __name__ == "__main__":
    main()
