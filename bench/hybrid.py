#!/usr/bin/env python3
"""The hybrid method (`[integrator] method = "hybrid"`: adaptive in flight, fixed-step
velocity Verlet inside contacts) on the nozzle stream, where it carries the history
tangential law (`[friction] tangential = "history"`, LIGGGHTS' `tangential history`).

usage: python3 bench/hybrid.py [--seeds K] [--ms T]   (default 4 seeds of 30 ms; about
       8 minutes, nearly all of it the fixed-step runs)

bench/scenes/stream_10k.toml (40,000 shots/s through the paper's nozzle) cut to T ms
(fed for T - 5 ms), friction 0.3 on every contact (shot-shot, specimen, bore), one thread:

1. Wall time of each method on seed 1: the adaptive method with the default (viscous)
   tangential law, and the history law on the hybrid method and on the fixed-step method
   (`method = "verlet"`, every shot stepping 20 ns in flight too), both at 20 ns.
2. What they compute, pooled over the seeds: the first impacts (count, mean normal and
   tangential speed, mean surface spin speed `|omega| R`, mean distance from the jet's
   axis) and all impacts, with the seeds' spread (standard deviation of the per-seed
   means); the history law on the two methods should agree within that spread. Shots
   collide in flight, so single trajectories are chaotic: distributions are compared.
"""
import csv
import json
import math
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import BIN, SCENES, option_value, options, run, usage_error  # noqa: E402

RADIUS = 0.4e-3  # the stream's shots, m

METHODS = [
    ("adaptive, viscous law", ""),
    ("hybrid 20 ns, history law", 'method = "hybrid"\nfixed_step_ns = 20\n'),
    ("verlet 20 ns, history law", 'method = "verlet"\nfixed_step_ns = 20\n'),
]


def scene(tmp, integrator, seed, ms):
    text = open(os.path.join(SCENES, "stream_10k.toml")).read()
    text = text.replace("duration_ms = 255.0", f"duration_ms = {ms}")
    text = text.replace("duration_ms = 250.0", f"duration_ms = {ms - 5.0}")
    law = "history" if integrator else "viscous"
    text = f"seed = {seed}\n" + text
    text += (
        "[friction]\nshot_shot = 0.3\nshot_specimen = 0.3\nshot_nozzle = 0.3\n"
        f'tangential = "{law}"\n[integrator]\n{integrator}'
    )
    path = os.path.join(tmp, f"stream_{law}_{seed}_{abs(hash(integrator))}.toml")
    open(path, "w").write(text)
    return path


def outcome(out):
    s = json.load(open(os.path.join(out, "summary.json")))
    rows = list(csv.DictReader(open(os.path.join(out, "impacts.csv"))))
    first = [r for r in rows if r["first_hit"] == "1"]

    def mean(f, rs):
        return sum(f(r) for r in rs) / max(len(rs), 1)

    spin = lambda r: RADIUS * math.sqrt(sum(float(r[f"omega_{c}_rad_s"]) ** 2 for c in "xyz"))
    return {
        "wall": s["wall_time_s"],
        "shot_steps": s["steps"]["shot_steps"],
        "impacts": len(rows),
        "first": len(first),
        "normal": mean(lambda r: float(r["normal_speed_m_s"]), first),
        "tangential": mean(lambda r: float(r["tangential_speed_m_s"]), first),
        "spin": mean(spin, first),
        "radius_mm": 1e3 * mean(lambda r: math.hypot(float(r["x_m"]), float(r["y_m"])), first),
        "collisions": s["contacts"]["shot_shot"],
    }


def main():
    argv = options(__doc__, valued=("--seeds", "--ms"))
    seeds = option_value(argv, "--seeds", int, 4)
    ms = option_value(argv, "--ms", float, 30.0)
    if seeds < 1 or not ms > 5.0:
        usage_error("--seeds must be at least 1 and --ms above 5 (the stream is fed for T - 5 ms)")
    results = {name: [] for name, _ in METHODS}
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(1, seeds + 1):
            for name, integrator in METHODS:
                path = scene(tmp, integrator, seed, ms)
                out = os.path.join(tmp, "out")
                run([BIN, "run", path, "--out", out, "--force", "-q", "-j", "1"], tmp)
                r = outcome(out)
                results[name].append(r)
                print(f"seed {seed}, {name}: {r['wall']:.2f} s, {r['first']} first impacts, "
                      f"mean normal speed {r['normal']:.3f} m/s", flush=True)
    print(f"\nstream_10k.toml cut to {ms} ms, friction 0.3, {seeds} seeds, one thread\n")
    print("| method | wall s (seed 1) | shot-steps (seed 1) | impacts | first impacts | "
          "mean normal speed m/s | mean tangential speed m/s | mean surface spin speed m/s | "
          "mean radius mm |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, _ in METHODS:
        rs = results[name]

        def cell(key, digits):
            vals = [r[key] for r in rs]
            # First impacts pooled: each seed's mean weighted by its count.
            if key in ("normal", "tangential", "spin", "radius_mm"):
                m = sum(r[key] * r["first"] for r in rs) / sum(r["first"] for r in rs)
            else:
                m = statistics.mean(vals)
            sd = statistics.stdev(vals) if len(vals) > 1 else 0.0
            return f"{m:.{digits}f} ± {sd:.{digits}f}"

        print(f"| {name} | {rs[0]['wall']:.2f} | {rs[0]['shot_steps']:,} | {cell('impacts', 0)} | "
              f"{cell('first', 0)} | {cell('normal', 2)} | {cell('tangential', 2)} | "
              f"{cell('spin', 2)} | {cell('radius_mm', 2)} |")


if __name__ == "__main__":
    main()
