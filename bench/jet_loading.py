#!/usr/bin/env python3
"""How heavily the shots load the jet, and what the share would cost the impact speeds
(docs/model.md, "How heavily the shots load the jet").

usage: python3 bench/jet_loading.py [--bin PATH] [--seeds N] [--feeds KG_MIN,...]
                                   [--diameters MM,...]
       (about 20 s with the defaults; needs the release binary, `cargo build --release`)

1. The share of the jet's momentum flow the shots take (summary.json
   `jet_loading.momentum_fraction`) for examples/s330_stream.toml at several feeds, over
   seeds (mean and its standard error): it follows the feed. And the same runs with
   `[jet] coupling = "momentum"`: the jet slowed by the share its shots take (`1 - f`,
   summary.json `jet_loading.air_speed_factor` f), the share the coupled runs' own first
   hits take, and the mean normal impact speed's drop over `1 - f`.
2. What a jet that lost a share `phi` of its momentum would do to a shot: the lone shot
   of examples/single_shot.toml (0.8 mm, and the other `--diameters`, from rest on the
   axis, drag only) in the
   paper's jet with its air `1 - phi` as fast at the same mass flow (so `1 / (1 - phi)`
   as dense): the exit speed scales as the square root of the supply temperature and the
   densities as the ambient density, so the scene's `temperature_k` is multiplied by
   `(1 - phi)^2` and `ambient_density_kg_m3` divided by `1 - phi`. It prints the impact
   speed's drop over `phi`: 1 where a shot follows the air's speed, 1/2 where it stays
   far below it (its speed then grows as the square root of the drag force, which at a
   fixed mass flow goes as the air's speed).
3. What neither the report nor the coupling counts: the momentum a shot takes from the
   air after its first hit. A lone shot (S330's 1.0 and 0.7 mm, entering the paper's
   bore at 5 m/s, gravity off) bounces on the plate under the jet for 40 ms: its
   momentum gain along the axis in its first flight (and the part of it gained in the
   bore), and over its flights after the first hit (each from 30 us after a hit, when
   the contact is over, to the next hit or the run's end), with the paper's free jet and
   with a 7 mm stagnation layer and its wall jet.
"""
import argparse
import csv
import json
import math
import os
import re
import statistics
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "peenflow")


def summary(binary, tmp, text):
    path = os.path.join(tmp, "scene.toml")
    open(path, "w").write(text)
    out = os.path.join(tmp, "out")
    subprocess.run([binary, "run", path, "--out", out, "-q", "--force"], check=True)
    return json.load(open(os.path.join(out, "summary.json")))


def example(binary, tmp, name):
    path = os.path.join(tmp, name + ".toml")
    subprocess.run([binary, "init", "--example", name, path], check=True, capture_output=True)
    return open(path).read()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=BIN)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--feeds", default="0.5,1.5,3,6,10")
    ap.add_argument("--diameters", default="0.8,0.3")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        stream = example(a.bin, tmp, "s330_stream")
        assert "mass_flow_kg_min = 3.0" in stream, "the example's feed moved"
        assert not re.search(r"(?m)^seed", stream), "the example sets a seed"
        print("S330 through the paper's 6 mm bore, 20 ms, %d seeds; one-way coupling (the paper's)" % a.seeds)
        print("and `coupling = \"momentum\"` (the jet slowed by a share 1 - f: the air's speed factor f)")
        print("| feed, kg/min | mass loading | share of the jet's momentum | per shot, kg m/s "
              "| normal speed, m/s | coupled: 1 - f | its run's share | normal speed, m/s | drop / (1 - f) |")
        print("|---|---|---|---|---|---|---|---|---|")
        mean = statistics.mean
        for q in [float(x) for x in a.feeds.split(",")]:
            rows = {"one_way": [], "momentum": []}
            for seed in range(1, a.seeds + 1):
                text = f"seed = {seed}\n" + stream.replace(
                    "mass_flow_kg_min = 3.0", f"mass_flow_kg_min = {q}")
                for coupling in rows:
                    sm = summary(a.bin, tmp, text + f'\n[jet]\ncoupling = "{coupling}"\n')
                    jl = sm["jet_loading"]
                    rows[coupling].append((jl["momentum_fraction"], jl["momentum_per_shot_kg_m_s"],
                                           sm["normal_speed_m_s"]["mean"], jl["air_speed_factor"],
                                           jl["mass_loading"]))
            free, coupled = rows["one_way"], rows["momentum"]
            shares = [r[0] for r in free]
            se = statistics.stdev(shares) / math.sqrt(len(shares)) if len(shares) > 1 else 0.0
            slow = 1.0 - mean(r[3] for r in coupled)
            v0, v1 = mean(r[2] for r in free), mean(r[2] for r in coupled)
            print(f"| {q:g} | {free[0][4]:.2f} | {100 * mean(shares):.1f} % ± {100 * se:.1f} "
                  f"| {mean(r[1] for r in free):.3g} | {v0:.2f} | {100 * slow:.1f} % "
                  f"| {100 * mean(r[0] for r in coupled):.1f} % | {v1:.2f} | {(1 - v1 / v0) / slow:.2f} |")

        lone = example(a.bin, tmp, "single_shot")
        assert "temperature_k = 293.0" in lone and "kappa = 1.4\n" in lone
        assert "ambient_density_kg_m3" not in lone and "diameter_mm = 0.8\n" in lone
        for d in [float(x) for x in a.diameters.split(",")]:
            print()
            print(f"A lone {d:g} mm SUJ-2 shot in the paper's jet slowed by phi at the same mass flow")
            print("| phi | impact speed, m/s | drop | drop / phi |")
            print("|---|---|---|---|")
            base = None
            for phi in [0.0, 0.02, 0.05, 0.10, 0.15, 0.25]:
                f = 1.0 - phi
                text = lone.replace("diameter_mm = 0.8\n", f"diameter_mm = {d!r}\n")
                text = text.replace("temperature_k = 293.0", f"temperature_k = {293.0 * f * f!r}")
                text = text.replace("kappa = 1.4\n",
                                    f"kappa = 1.4\nambient_density_kg_m3 = {1.205 / f!r}\n")
                v = summary(a.bin, tmp, text)["normal_speed_m_s"]["mean"]
                if base is None:
                    base = v
                    print(f"| 0 | {v:.2f} | | |")
                    continue
                drop = 1.0 - v / base
                print(f"| {phi:g} | {v:.2f} | {100 * drop:.1f} % | {drop / phi:.2f} |")

        print()
        print("A lone shot's momentum gain along the axis, per unit mass (m/s), in its first flight "
              "and after its first hit, 40 ms")
        print("| diameter, mm | offset, mm | air | first flight (in the bore) | hits | after the first hit "
              "| after / first |")
        print("|---|---|---|---|---|---|---|")
        for d in [1.0, 0.7]:
            for r in [0.0, 1.0, 2.0]:
                for air, extra in [("free jet", ""),
                                   ("layer", "[jet]\nstagnation_layer_mm = 7.0\nwall_jet = true\n")]:
                    first, bore, after, hits = after_first_hit(a.bin, tmp, d, r, extra)
                    print(f"| {d:g} | {r:g} | {air} | {first:.1f} ({bore:.1f}) | {hits} | {after:.1f} "
                          f"| {after / first:.2f} |")


def lone_at(binary, tmp, d, r, extra, duration_ms):
    """A lone shot of `d` mm entering the bore `r` mm off the axis at 5 m/s, flown for
    `duration_ms`: its impacts and its state at the end."""
    text = (f"duration_ms = {duration_ms!r}\n[shots]\ndiameter_mm = {d}\n[shots.feed]\n"
            f"type = \"list\"\n[[shots.feed.shots]]\nposition_mm = [{r}, 0.0, 140.0]\n"
            f"velocity_m_s = [0.0, 0.0, -5.0]\n[effects]\ngravity = false\n{extra}")
    path = os.path.join(tmp, "lone.toml")
    open(path, "w").write(text)
    out = os.path.join(tmp, "lone")
    subprocess.run([binary, "run", path, "--out", out, "-q", "--force"], check=True)
    impacts = list(csv.DictReader(open(os.path.join(out, "impacts.csv"))))
    shot = list(csv.DictReader(open(os.path.join(out, "shots.csv"))))[0]
    return impacts, shot


def after_first_hit(binary, tmp, d, r, extra):
    """(first flight's gain, of it in the bore, gain after the first hit, hits) along the
    axis (down), per unit mass, m/s."""
    impacts, end = lone_at(binary, tmp, d, r, extra, 40.0)
    times = [float(i["time_s"]) for i in impacts]
    down = [-float(i["vz_m_s"]) for i in impacts]
    # Leaving the bore (100 mm above the plate): the exit's time by bisection.
    lo, hi = 0.0, times[0] * 1e3
    for _ in range(24):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if float(lone_at(binary, tmp, d, r, extra, mid)[1]["z_m"]) > 0.1 else (lo, mid)
    bore = -float(lone_at(binary, tmp, d, r, extra, lo)[1]["vz_m_s"]) - 5.0
    after = 0.0
    for k, t in enumerate(times):
        leaving = -float(lone_at(binary, tmp, d, r, extra, (t + 30e-6) * 1e3)[1]["vz_m_s"])
        arriving = down[k + 1] if k + 1 < len(times) else -float(end["vz_m_s"])
        after += arriving - leaving
    return down[0] - 5.0, bore, after, len(times)


if __name__ == "__main__":
    main()
