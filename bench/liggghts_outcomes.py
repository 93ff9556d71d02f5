#!/usr/bin/env python3
"""What peenflow and LIGGGHTS 3.8 compute on the same scene: LIGGGHTS' stream.in (10,000
steel shots of 0.8 mm at 5 % volume fraction falling at 70 m/s onto a steel wall, rebounds
meeting the incoming shots) and peenflow's bench/scenes/pack_stream_10k.toml, frictionless
and with LIGGGHTS' friction 0.3, over several seeds of each code.

usage: python3 bench/liggghts_outcomes.py [--seeds K]   (default 4 seeds; about 2 minutes)

Needs `liggghts` (apt-get install -y liggghts) and reads stream.in from
../shared/bench/liggghts (or $LIGGGHTS_INPUTS), as bench/bench.py does.

The shots collide with each other: single trajectories are chaotic, and the two codes
place their shots with different random generators. What is compared is therefore the
state of the shots at 50, 100, 150 and 170 us as distributions, pooled over the seeds
(per-seed spread given as the standard deviation), in the column's central region: a
square 10 mm in from each side. LIGGGHTS' column is periodic in x and y and peenflow's has
free sides (shots scattered outwards at the edge fly away instead of meeting the
neighbouring column's), so the whole-column totals differ by that edge; the centre does
not feel it within 170 us (the statistics hold from 5 mm to 20 mm in).

Printed per time and friction: shots in the region, kinetic energy per shot, fraction
moving up, mean vertical velocity, mean horizontal speed, speed percentiles, and the
Kolmogorov-Smirnov distance between the two codes' pooled vertical velocities (to 0.01
m/s) next to the same distance between two halves of each code's own seeds (the sampling
floor).
"""
import csv
import math
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import BIN, ROOT, SCENES, liggghts_inputs, run  # noqa: E402

DT_NS = 20.0  # stream.in's step
DUMP_EVERY = 2500  # LIGGGHTS steps between dumps: 50, 100, 150 us; plus the end
END_STEP = 8502  # two setup steps (insertion, step check) and 8,500 timed steps
MARGIN = 0.010  # m: the central region's distance from each side
MASS = 7850.0 * math.pi / 6.0 * 0.0008**3
# insert/pack seeds (LIGGGHTS wants primes above 10,000); the first is stream.in's own.
LIGGGHTS_SEEDS = [49979687, 49979693, 49979737, 49979767, 49979777, 49979791, 49979813, 49979819]


def liggghts_input(text, mu, seed):
    """stream.in with friction `mu`, insertion seed `seed`, and dumps of every shot's
    position and velocity every DUMP_EVERY steps and at the end."""
    fric = "coefficientFriction peratomtypepair 2 0.3 0.3 0.3 0.3"
    assert fric in text and "seed 49979687" in text and text.rstrip().endswith("run ${steps}"), \
        "stream.in changed: update bench/liggghts_outcomes.py"
    text = text.replace(fric, f"coefficientFriction peratomtypepair 2 {mu} {mu} {mu} {mu}")
    text = text.replace("seed 49979687", f"seed {seed}")
    head, _, _ = text.rstrip().rpartition("run ${steps}")
    return (head + f"dump d all custom {DUMP_EVERY} dump.*.txt id x y z vx vy vz\n"
            + "run ${steps}\nundump d\n"
            + f"dump e all custom 1 dump.{END_STEP}.txt id x y z vx vy vz\nrun 0\n")


def read_dump(path):
    lines = open(path).read().split("ITEM: ATOMS")[1].strip().split("\n")[1:]
    return [tuple(float(x) for x in line.split()[1:7]) for line in lines]


def read_shots(path):
    return [tuple(float(r[k]) for k in ("x_m", "y_m", "z_m", "vx_m_s", "vy_m_s", "vz_m_s"))
            for r in csv.DictReader(open(path)) if r["status"] == "active"]


def central(points, width):
    return [p for p in points if MARGIN <= p[0] <= width - MARGIN and MARGIN <= p[1] <= width - MARGIN]


def stats(points):
    n = len(points)
    speed = sorted(math.sqrt(p[3] ** 2 + p[4] ** 2 + p[5] ** 2) for p in points)
    pct = lambda q: speed[min(n - 1, int(q * n))]
    return {
        "n": n,
        "ke_mj": 1e3 * sum(0.5 * MASS * v * v for v in speed) / n,
        "up": sum(1 for p in points if p[5] > 0) / n,
        "vz": sum(p[5] for p in points) / n,
        "vh": sum(math.hypot(p[3], p[4]) for p in points) / n,
        "p10": pct(0.1),
        "p50": pct(0.5),
        "p90": pct(0.9),
    }


def ks(a, b):
    """Two-sample Kolmogorov-Smirnov distance of velocities rounded to 0.01 m/s (the shots
    not yet hit all fall at -70 m/s plus gravity's 5e-4 m/s, which the two codes add up
    to differently in the last digits: unrounded, that alone gives a distance of 0.6)."""
    a, b = sorted(round(x, 2) for x in a), sorted(round(x, 2) for x in b)
    i = j = 0
    d = 0.0
    while i < len(a) and j < len(b):
        x = min(a[i], b[j])
        while i < len(a) and a[i] <= x:
            i += 1
        while j < len(b) and b[j] <= x:
            j += 1
        d = max(d, abs(i / len(a) - j / len(b)))
    return d


def main():
    argv = sys.argv[1:]
    seeds = 4
    if "--seeds" in argv:
        seeds = int(argv[argv.index("--seeds") + 1])
    if not 2 <= seeds <= len(LIGGGHTS_SEEDS):
        sys.exit(f"--seeds must be 2 to {len(LIGGGHTS_SEEDS)}")
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    steps = [DUMP_EVERY * k for k in range(1, END_STEP // DUMP_EVERY + 1)] + [END_STEP]
    scene = open(os.path.join(SCENES, "pack_stream_10k.toml")).read()
    assert "duration_ms = 0.17\n" in scene
    width = 0.073223299  # stream.in's L for N = 10,000 (and the scene's column)
    with tempfile.TemporaryDirectory() as tmp:
        liggghts_inputs(tmp, ("stream.in",))
        text = open(os.path.join(tmp, "stream.in")).read()
        # states[(mu, code)][step] = list over seeds of central-region shot lists
        states = {}
        for mu in (0.0, 0.3):
            for k in range(seeds):
                d = os.path.join(tmp, f"lg_{mu}_{k}")
                os.mkdir(d)
                open(os.path.join(d, "in.stream"), "w").write(liggghts_input(text, mu, LIGGGHTS_SEEDS[k]))
                run(["liggghts", "-in", "in.stream", "-var", "N", "10000", "-log", "log", "-screen", "screen"], d)
                for s in steps:
                    states.setdefault((mu, "LIGGGHTS"), {}).setdefault(s, []).append(
                        central(read_dump(os.path.join(d, f"dump.{s}.txt")), width))
                for s in steps:
                    ms = s * DT_NS * 1e-6
                    t = scene.replace("duration_ms = 0.17\n", f"duration_ms = {ms:.6g}\nseed = {k + 1}\n")
                    t = t.replace("[effects]", f"[friction]\nshot_specimen = {mu}\nshot_shot = {mu}\n[effects]")
                    path = os.path.join(tmp, "pf.toml")
                    open(path, "w").write(t)
                    out = os.path.join(tmp, f"pf_{mu}_{k}_{s}")
                    run([BIN, "run", path, "--out", out, "-q", "-j", "1"], tmp)
                    states.setdefault((mu, "peenflow"), {}).setdefault(s, []).append(
                        central(read_shots(os.path.join(out, "shots.csv")), width))
                print(f"friction {mu}: seed {k + 1} of {seeds} done", file=sys.stderr)
        keys = ("ke_mj", "up", "vz", "vh", "p10", "p50", "p90")
        fmt = {"ke_mj": "{:.4f}", "up": "{:.4f}", "vz": "{:.2f}", "vh": "{:.2f}", "p10": "{:.2f}", "p50": "{:.2f}", "p90": "{:.2f}"}
        print(f"central region ({1e3 * MARGIN:g} mm in from each side), {seeds} seeds of each code; "
              "pooled value (per-seed standard deviation)")
        print()
        print("| friction | time us | code | shots in region | KE per shot mJ | moving up | mean vz m/s | mean horizontal speed m/s "
              "| speed p10 / p50 / p90 m/s | KS distance of vz: codes (own seeds' halves) |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for mu in (0.0, 0.3):
            for s in steps:
                pooled = {}
                for code in ("LIGGGHTS", "peenflow"):
                    per = states[(mu, code)][s]
                    pooled[code] = [p for pts in per for p in pts]
                    st = stats(pooled[code])
                    sd = {key: statistics.stdev(stats(pts)[key] for pts in per) for key in keys}
                    cell = lambda key: f"{fmt[key].format(st[key])} ({fmt[key].format(sd[key])})"
                    half = seeds // 2
                    own = ks([p[5] for pts in per[:half] for p in pts], [p[5] for pts in per[half:] for p in pts])
                    if code == "LIGGGHTS":
                        dist = f"({own:.3f})"
                    else:
                        dist = f"{ks([p[5] for p in pooled['LIGGGHTS']], [p[5] for p in pooled['peenflow']]):.3f} ({own:.3f})"
                    print(f"| {mu} | {s * DT_NS * 1e-3:g} | {code} | {st['n'] / seeds:.0f} | {cell('ke_mj')} | {cell('up')} | "
                          f"{cell('vz')} | {cell('vh')} | {st['p10']:.2f} / {st['p50']:.2f} / {st['p90']:.2f} | {dist} |")
                sys.stdout.flush()


if __name__ == "__main__":
    main()
