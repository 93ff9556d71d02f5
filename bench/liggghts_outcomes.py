#!/usr/bin/env python3
"""What peenflow and LIGGGHTS 3.8 compute on the same scene: LIGGGHTS' stream.in (10,000
steel shots of 0.8 mm at 5 % volume fraction falling at 70 m/s onto a steel wall, rebounds
meeting the incoming shots) and peenflow's bench/scenes/pack_stream_10k.toml, frictionless
and with LIGGGHTS' friction 0.3, over several seeds of each code.

usage: python3 bench/liggghts_outcomes.py [--seeds K]   (default 4 seeds; about 3 minutes)

Needs `liggghts` (apt-get install -y liggghts) and reads stream.in from
../shared/bench/liggghts (or $LIGGGHTS_INPUTS), as bench/bench.py does.

First, one shot onto the wall at 70 m/s from 0 to 80 degrees, with friction 0.3: the
rebound in each code next to rigid-body impact theory (LIGGGHTS' tangential spring against
peenflow's default, spring-free tangential law, and against peenflow's tangential spring
with history, `tangential = "history"` on its fixed-step method at 20 ns, since session
42). With friction the stream is also run with that law (about 1.5 minutes more), on
windows and on the event scheduler (`scheduler = "events"`, since session 43).

In the stream the shots collide with each other: single trajectories are chaotic, and the two codes
place their shots with different random generators. What is compared is therefore the
state of the shots at 50, 100, 150 and 170 us as distributions, pooled over the seeds
(per-seed spread given as the standard deviation), in the column's central region: a
square 10 mm in from each side. LIGGGHTS' column is periodic in x and y and peenflow's has
free sides (shots scattered outwards at the edge fly away instead of meeting the
neighbouring column's), so the whole-column totals differ by that edge; the centre does
not feel it within 170 us (the statistics hold from 5 mm to 20 mm in).

Printed per time and friction: shots in the region, kinetic energy per shot, fraction
moving up, mean vertical velocity, mean horizontal speed, speed percentiles, and the
Kolmogorov-Smirnov distance between the two codes' pooled vertical velocities (to 0.1
m/s) next to the same distance between two halves of each code's own seeds (the sampling
floor). Then the impacts on the wall in the region over the run (what FE users take):
count, first hits, normal-speed mean, percentiles and bands, tangential speed, impacts
per 20 us, and the same distance for the normal speeds. LIGGGHTS records no impacts:
they are read off a dump of the shots about to touch the wall (`liggghts_impacts`).
"""
import csv
import math
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import (  # noqa: E402
    BIN, ROOT, SCENES, liggghts_inputs, option_value, options, run, usage_error)

DT_NS = 20  # stream.in's step, ns
DUMP_EVERY = 2500  # LIGGGHTS steps between dumps: 50, 100, 150 us; plus the end
END_STEP = 8502  # two setup steps (insertion, step check) and 8,500 timed steps
MARGIN = 0.010  # m: the central region's distance from each side
MASS = 7850.0 * math.pi / 6.0 * 0.0008**3
RADIUS = 0.0004
IMPACT_EVERY = 10  # LIGGGHTS steps between the impact dumps (200 ns)
IMPACT_WINDOW = 50e-6  # m: shots this close to touching are dumped (any speed below 250 m/s
# crosses it in more than IMPACT_EVERY steps, so each approach is seen at least once)
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
    # Shots about to touch the wall (centre within IMPACT_WINDOW of touching, moving
    # down), every IMPACT_EVERY steps: see `liggghts_impacts`.
    window = f"{RADIUS + IMPACT_WINDOW:.6g}"
    return (head + f"dump d all custom {DUMP_EVERY} dump.*.txt id x y z vx vy vz omegax omegay omegaz\n"
            + f"dump imp all custom {IMPACT_EVERY} dump.impacts id x y z vx vy vz omegax omegay omegaz\n"
            + f"dump_modify imp thresh z < {window} thresh z > {RADIUS} thresh vz < 0.0\n"
            + "run ${steps}\nundump d\nundump imp\n"
            + f"dump e all custom 1 dump.{END_STEP}.txt id x y z vx vy vz omegax omegay omegaz\nrun 0\n")


def read_dump(path):
    """(position, velocity, spin) of every shot in a LIGGGHTS dump, in the order of their
    ids (LIGGGHTS writes them in its own order)."""
    head, _, body = open(path).read().partition("ITEM: ATOMS")
    lines = body.strip().split("\n")
    assert lines[0].split() == ["id", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"], lines[0]
    rows = sorted((int(line.split()[0]), line.split()[1:10]) for line in lines[1:])
    return [tuple(float(x) for x in row) for _, row in rows]


def liggghts_impacts(path, by_id=False):
    """LIGGGHTS' wall impacts from the approach dumps: a shot seen moving down with its
    centre less than IMPACT_EVERY steps of its own speed above touching touches before the
    next dump (gravity moves it by 2e-10 m meanwhile); its impact is taken where its free
    path touches. Returns (time, x, y, normal speed, tangential speed, first hit, surface
    spin speed |omega| R), or with `by_id` (id, time, normal speed)."""
    out, seen = [], set()
    text = open(path).read()
    for block in text.split("ITEM: TIMESTEP\n")[1:]:
        lines = block.split("\n")
        step = int(lines[0])
        k = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
        assert lines[k].split()[2:] == ["id", "x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"], lines[k]
        for line in lines[k + 1:]:
            if not line.strip():
                continue
            i, *rest = line.split()
            x, y, z, vx, vy, vz, wx, wy, wz = map(float, rest)
            tau = (z - RADIUS) / -vz
            if tau < IMPACT_EVERY * DT_NS * 1e-9:
                spin = math.sqrt(wx * wx + wy * wy + wz * wz) * RADIUS
                t = step * DT_NS * 1e-9 + tau
                if by_id:
                    out.append((int(i), t, -vz))
                else:
                    out.append((t, x + vx * tau, y + vy * tau, -vz, math.hypot(vx, vy), i not in seen, spin))
                seen.add(i)
    return out


def read_impacts(path):
    spin = lambda r: math.sqrt(sum(float(r[f"omega_{a}_rad_s"]) ** 2 for a in "xyz")) * RADIUS
    return [(float(r["time_s"]), float(r["x_m"]), float(r["y_m"]), float(r["normal_speed_m_s"]),
             float(r["tangential_speed_m_s"]), r["first_hit"] == "1", spin(r)) for r in csv.DictReader(open(path))]


def read_shots(path):
    keys = ("x_m", "y_m", "z_m", "vx_m_s", "vy_m_s", "vz_m_s", "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s")
    return [tuple(float(r[k]) for k in keys) for r in csv.DictReader(open(path)) if r["status"] == "active"]


def central(points, width, at=0):
    """The points whose x, y (at indices `at`, `at + 1`) lie in the central region."""
    return [p for p in points if MARGIN <= p[at] <= width - MARGIN and MARGIN <= p[at + 1] <= width - MARGIN]


def stats(points):
    n = len(points)
    speed = sorted(math.sqrt(p[3] ** 2 + p[4] ** 2 + p[5] ** 2) for p in points)
    pct = lambda q: speed[min(n - 1, int(q * n))]
    return {
        "n": n,
        "ke_mj": 1e3 * sum(0.5 * MASS * v * v for v in speed) / n,
        # spin energy, solid sphere: I = 2/5 m R^2
        "rot_mj": 1e3 * sum(0.2 * MASS * RADIUS**2 * (p[6] ** 2 + p[7] ** 2 + p[8] ** 2) for p in points) / n,
        "up": sum(1 for p in points if p[5] > 0) / n,
        "vz": sum(p[5] for p in points) / n,
        "vh": sum(math.hypot(p[3], p[4]) for p in points) / n,
        "p10": pct(0.1),
        "p50": pct(0.5),
        "p90": pct(0.9),
    }


def ks(a, b):
    """Two-sample Kolmogorov-Smirnov distance of velocities rounded to 0.1 m/s. Many shots
    share a velocity: those not yet hit all fall at -70 m/s plus gravity's 5e-4 m/s, which
    the two codes add up differently in the last digits (unrounded, that alone gives a
    distance of 0.6), and those rebounding from their first impact leave at 49.000 m/s in
    peenflow and at 49.008 m/s in LIGGGHTS (its 20 ns step's restitution error, 1.7e-4:
    rounded to 0.01 m/s, that alone gives 0.027 at 50 us)."""
    a, b = sorted(round(x, 1) for x in a), sorted(round(x, 1) for x in b)
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

def liggghts_contacts(mu, e_wall=0.7):
    """stream.in's shots, contact models and step, as LIGGGHTS input lines (after the box
    exists): restitution 0.9 between shots and `e_wall` on the wall, friction `mu`."""
    return ["neighbor 0.0002 bin", "neigh_modify delay 0",
            "fix m1 all property/global youngsModulus peratomtype 2.1e11 2.1e11",
            "fix m2 all property/global poissonsRatio peratomtype 0.3 0.3",
            f"fix m3 all property/global coefficientRestitution peratomtypepair 2 0.9 {e_wall} {e_wall} 0.9",
            f"fix m4 all property/global coefficientFriction peratomtypepair 2 {mu} {mu} {mu} {mu}",
            "pair_style gran model hertz tangential history", "pair_coeff * *", "timestep 2e-8",
            "fix zwall all wall/gran model hertz tangential history primitive type 2 zplane 0.0"]


LIGGGHTS_HEAD = ["atom_style granular", "atom_modify map array", "boundary f f f", "newton off",
                 "communicate single vel yes", "units si", "hard_particles yes"]


OBLIQUE_ANGLES = (0, 10, 20, 30, 40, 50, 60, 70, 80)  # degrees from the wall's normal


def oblique(tmp, mu=0.3, e=0.7, speed=70.0):
    """One shot onto the wall at `speed` from each angle of OBLIQUE_ANGLES, friction `mu`,
    no gravity, in LIGGGHTS (stream.in's materials, contact models and 20 ns step) and in
    peenflow; the rebound's tangential and normal velocities and the surface spin speed
    omega R, next to rigid-body impact theory (Brach 1991: sliding throughout if
    v_t > 7/2 mu (1 + e) v_n, else the slip stops and v_t' = omega' R = 5/7 v_t)."""
    gap = 10e-6
    lines = LIGGGHTS_HEAD + [
        f"region box block -0.005 0.005 -0.001 {0.002 * len(OBLIQUE_ANGLES) + 0.001} -0.001 0.005 units box",
        "create_box 2 box"] + liggghts_contacts(mu, e)
    lines += [f"create_atoms 1 single 0.0 {0.002 * k} {RADIUS + gap} units box" for k in range(len(OBLIQUE_ANGLES))]
    lines += ["set group all diameter 0.0008", "set group all density 7850"]
    shots = ""
    for k, a in enumerate(OBLIQUE_ANGLES):
        vt, vn = speed * math.sin(math.radians(a)), speed * math.cos(math.radians(a))
        lines += [f"group g{k} id {k + 1}", f"velocity g{k} set {vt!r} 0 {-vn!r} units box"]
        shots += (f"[[shots.feed.shots]]\nposition_mm = [0.0, {2.0 * k}, {(RADIUS + gap) * 1e3!r}]\n"
                  f"velocity_m_s = [{vt!r}, 0.0, {-vn!r}]\n")
    lines += ["fix integr all nve/sphere", "run 1000",
              "dump e all custom 1 dump.oblique id x y z vx vy vz omegax omegay omegaz", "run 0"]
    d = os.path.join(tmp, "oblique")
    os.mkdir(d)
    open(os.path.join(d, "in.oblique"), "w").write("\n".join(lines) + "\n")
    run(["liggghts", "-in", "in.oblique", "-log", "log", "-screen", "screen"], d)
    lg = read_dump(os.path.join(d, "dump.oblique"))
    scene = (f"duration_ms = 0.02\n[shots]\ndiameter_mm = 0.8\nmaterial = \"table2-steel\"\n[shots.feed]\n"
             f"type = \"list\"\n{shots}[restitution]\nshot_specimen = {e}\n[friction]\nshot_specimen = {mu}\n"
             "[effects]\ndrag = false\nlateral_force = false\ngravity = false\nspecimen_contact = true\n"
             "shot_shot_contact = false\nnozzle_wall_contact = false\n")
    runs = []
    for name, law in (("pf", ""), ("pf_history", HISTORY)):
        path = os.path.join(d, f"{name}.toml")
        open(path, "w").write(scene.replace("[effects]", law + "[effects]"))
        run([BIN, "run", path, "--out", os.path.join(d, name), "-q", "-j", "1"], d)
        runs.append(read_shots(os.path.join(d, name, "shots.csv")))
    pf, ph = runs
    print(f"One shot onto the wall at {speed:g} m/s, friction {mu}, restitution {e}: rebound tangential and normal "
          "velocity and surface spin speed omega R, m/s")
    print()
    print("| angle from normal, deg | incoming v_t | LIGGGHTS v_t' / v_n' / omega R | peenflow v_t' / v_n' / omega R "
          "| peenflow, history law, Verlet 20 ns | rigid-body theory v_t' / omega R (regime) |")
    print("|---|---|---|---|---|---|")
    for k, a in enumerate(OBLIQUE_ANGLES):
        vt, vn = speed * math.sin(math.radians(a)), speed * math.cos(math.radians(a))
        slide = vt > 3.5 * mu * (1 + e) * vn
        theory = vt - mu * (1 + e) * vn if slide else 5 / 7 * vt
        spin = 2.5 * mu * (1 + e) * vn if slide else theory
        cells = []
        for p in (lg[k], pf[k], ph[k]):
            # y spin: a shot moving in +x on the plane z = 0 spins about +y
            cells.append(f"{p[3]:.2f} / {p[5]:.2f} / {p[7] * RADIUS:.2f}")
        print(f"| {a} | {vt:.2f} | {' | '.join(cells)} | {theory:.2f} / {spin:.2f} ({'sliding' if slide else 'sticking'}) |")
    print()
    sys.stdout.flush()


def same_start(tmp, seed=12345):
    """The stream from one packing in both codes: LIGGGHTS reads peenflow's initial
    positions (a data file) and runs with free sides, as peenflow's column has them, and
    no friction. Each shot's first impact is compared, shot by shot, with peenflow at its
    default tolerance, at 1e-9, and with its fixed-step method at LIGGGHTS' 20 ns; per
    band of first-impact time, the share of shots whose first impact is the same (within
    1 ns and 1e-3 of the normal speed) and the median time difference."""
    import random
    rng = random.Random(seed)
    n, d, width, z0, height = 10_000, 2 * RADIUS, 0.073223299, 0.001, 0.010
    lo, hi = (RADIUS, RADIUS, z0 + RADIUS), (width - RADIUS, width - RADIUS, z0 + height - RADIUS)
    cells, pts = {}, []
    while len(pts) < n:
        p = tuple(rng.uniform(lo[k], hi[k]) for k in range(3))
        c = tuple(int(p[k] / d) for k in range(3))
        near = (q for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for q in cells.get((c[0] + dx, c[1] + dy, c[2] + dz), ()))
        if all(sum((p[k] - q[k]) ** 2 for k in range(3)) >= d * d for q in near):
            pts.append(p)
            cells.setdefault(c, []).append(p)
    dd = os.path.join(tmp, "same_start")
    os.mkdir(dd)
    with open(os.path.join(dd, "shots.data"), "w") as f:
        f.write(f"peenflow's packing\n\n{n} atoms\n2 atom types\n\n-0.02 {width + 0.02!r} xlo xhi\n"
                f"-0.02 {width + 0.02!r} ylo yhi\n-0.001 0.02 zlo zhi\n\nAtoms\n\n")
        f.writelines(f"{i + 1} 1 {d} 7850 {p[0]!r} {p[1]!r} {p[2]!r}\n" for i, p in enumerate(pts))
        f.write("\nVelocities\n\n")
        f.writelines(f"{i + 1} 0 0 -70 0 0 0\n" for i in range(n))
    fmt = '"%d' + " %.17g" * 9 + '"'
    lines = LIGGGHTS_HEAD + ["read_data shots.data"] + liggghts_contacts(0.0) + [
             "fix gravi all gravity 9.81 vector 0.0 0.0 -1.0",
             "fix integr all nve/sphere", "thermo_modify lost ignore norm no",
             f"dump imp all custom {IMPACT_EVERY} dump.impacts id x y z vx vy vz omegax omegay omegaz",
             f"dump_modify imp format {fmt}",
             f"dump_modify imp thresh z < {RADIUS + IMPACT_WINDOW:.6g} thresh z > {RADIUS} thresh vz < 0.0",
             f"run {END_STEP}"]
    open(os.path.join(dd, "in.same"), "w").write("\n".join(lines) + "\n")
    run(["liggghts", "-in", "in.same", "-log", "log", "-screen", "screen"], dd)
    lg = {}
    for imp in liggghts_impacts(os.path.join(dd, "dump.impacts"), by_id=True):
        lg.setdefault(imp[0], []).append(imp[1:])
    shots = "".join(f"[[shots.feed.shots]]\nposition_mm = [{p[0] * 1e3!r}, {p[1] * 1e3!r}, {p[2] * 1e3!r}]\n"
                    "velocity_m_s = [0.0, 0.0, -70.0]\n" for p in pts)
    base = (f"duration_ms = {END_STEP * DT_NS * 1e-6:.6g}\n[shots]\ndiameter_mm = 0.8\nmaterial = \"table2-steel\"\n"
            f"[shots.feed]\ntype = \"list\"\n{shots}[restitution]\nshot_specimen = 0.7\nshot_shot = 0.9\n"
            "{integrator}[effects]\ndrag = false\nlateral_force = false\ngravity = true\nspecimen_contact = true\n"
            "shot_shot_contact = true\nnozzle_wall_contact = false\n")
    runs = {}
    for tag, integ in (("default", ""), ("1e-9", "[integrator]\ntolerance = 1e-9\n"),
                       ("verlet", "[integrator]\nmethod = \"verlet\"\nfixed_step_ns = 20\n")):
        path = os.path.join(dd, f"{tag}.toml")
        open(path, "w").write(base.replace("{integrator}", integ))
        run([BIN, "run", path, "--out", os.path.join(dd, tag), "-q", "-j", "1"], dd)
        runs[tag] = {}
        for r in csv.DictReader(open(os.path.join(dd, tag, "impacts.csv"))):
            runs[tag].setdefault(int(r["shot"]) + 1, []).append((float(r["time_s"]), float(r["normal_speed_m_s"])))
    edges = [0, 20e-6, 40e-6, 60e-6, 80e-6, 100e-6, 120e-6, 1.0]
    def bands(a, b):
        cells = []
        for lo_t, hi_t in zip(edges, edges[1:]):
            firsts = [(a[i][0], b.get(i, [None])[0]) for i in a if lo_t <= a[i][0][0] < hi_t]
            both = [(x, y) for x, y in firsts if y is not None]
            same = sum(1 for x, y in both if abs(y[0] - x[0]) < 1e-9 and abs(y[1] / x[1] - 1) < 1e-3)
            dt = sorted(abs(y[0] - x[0]) for x, y in both)
            median = f" ({dt[len(dt) // 2]:.0e} s)" if dt else ""
            cells.append(f"{100 * same / len(firsts):.1f} %{median}" if firsts else "")
        return cells
    print(f"The same packing in both codes (LIGGGHTS with free sides, frictionless): first impacts, shot by shot. "
          f"Impacts in all: LIGGGHTS {sum(map(len, lg.values()))}, peenflow {sum(map(len, runs['default'].values()))}. "
          "Per band of first-impact time: the share of shots whose first impact is the same in both runs (within "
          "1 ns and 1e-3 of the normal speed), and the median time difference")
    print()
    head = " | ".join(f"{lo_t * 1e6:g}-{hi_t * 1e6:g} us" if hi_t < 1 else f"from {lo_t * 1e6:g} us"
                      for lo_t, hi_t in zip(edges, edges[1:]))
    print(f"| runs compared | {head} |")
    print("|---|" + "---|" * (len(edges) - 1))
    for label, a, b in (("LIGGGHTS, peenflow default tolerance", lg, runs["default"]),
                        ("LIGGGHTS, peenflow tolerance 1e-9", lg, runs["1e-9"]),
                        ("peenflow tolerance 1e-9, default tolerance", runs["1e-9"], runs["default"]),
                        ("LIGGGHTS, peenflow velocity Verlet 20 ns", lg, runs["verlet"]),
                        ("peenflow tolerance 1e-9, velocity Verlet 20 ns", runs["1e-9"], runs["verlet"])):
        print(f"| {label} | {' | '.join(bands(a, b))} |")
    print()
    sys.stdout.flush()


# With friction, peenflow runs with its default (viscous) tangential law and with the
# tangential spring with history, LIGGGHTS' own law, on its fixed-step method at
# LIGGGHTS' step (the history law's method; since session 42).
HISTORY = 'tangential = "history"\n[integrator]\nmethod = "verlet"\nfixed_step_ns = 20\n'


def peenflow_codes(mu):
    """The peenflow runs compared at friction `mu`: (label, scene lines before [effects])."""
    runs = [("peenflow", "")]
    if mu > 0:
        runs.append(("peenflow, history law, Verlet 20 ns", HISTORY))
        # The same on the event scheduler: free flight in closed form (since session 43).
        runs.append(("peenflow, history law, Verlet 20 ns on events", HISTORY + 'scheduler = "events"\n'))
    return runs


def main():
    argv = options(__doc__, valued=("--seeds",))
    seeds = option_value(argv, "--seeds", int, 4)
    if not 2 <= seeds <= len(LIGGGHTS_SEEDS):
        usage_error(f"--seeds must be 2 to {len(LIGGGHTS_SEEDS)}")
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    steps = [DUMP_EVERY * k for k in range(1, END_STEP // DUMP_EVERY + 1)] + [END_STEP]
    scene = open(os.path.join(SCENES, "pack_stream_10k.toml")).read()
    assert "duration_ms = 0.17\n" in scene
    width = 0.073223299  # stream.in's L for N = 10,000 (and the scene's column)
    with tempfile.TemporaryDirectory() as tmp:
        liggghts_inputs(tmp, ("stream.in",))
        text = open(os.path.join(tmp, "stream.in")).read()
        oblique(tmp)
        same_start(tmp)
        # states[(mu, code)][step] = list over seeds of central-region shot lists
        states = {}
        # impacts[(mu, code)] = list over seeds of central-region impact lists
        impacts = {}
        for mu in (0.0, 0.3):
            for k in range(seeds):
                d = os.path.join(tmp, f"lg_{mu}_{k}")
                os.mkdir(d)
                open(os.path.join(d, "in.stream"), "w").write(liggghts_input(text, mu, LIGGGHTS_SEEDS[k]))
                run(["liggghts", "-in", "in.stream", "-var", "N", "10000", "-log", "log", "-screen", "screen"], d)
                for s in steps:
                    states.setdefault((mu, "LIGGGHTS"), {}).setdefault(s, []).append(
                        central(read_dump(os.path.join(d, f"dump.{s}.txt")), width))
                impacts.setdefault((mu, "LIGGGHTS"), []).append(
                    central(liggghts_impacts(os.path.join(d, "dump.impacts")), width, at=1))
                for code, law in peenflow_codes(mu):
                    for s in steps:
                        ms = s * DT_NS * 1e-6
                        t = scene.replace("duration_ms = 0.17\n", f"duration_ms = {ms:.6g}\nseed = {k + 1}\n")
                        t = t.replace("[effects]", f"[friction]\nshot_specimen = {mu}\nshot_shot = {mu}\n{law}[effects]")
                        path = os.path.join(tmp, "pf.toml")
                        open(path, "w").write(t)
                        out = os.path.join(tmp, f"pf_{mu}_{k}_{s}")
                        run([BIN, "run", path, "--out", out, "-q", "-j", "1", "--force"], tmp)
                        states.setdefault((mu, code), {}).setdefault(s, []).append(
                            central(read_shots(os.path.join(out, "shots.csv")), width))
                        if s == END_STEP:
                            impacts.setdefault((mu, code), []).append(
                                central(read_impacts(os.path.join(out, "impacts.csv")), width, at=1))
                print(f"friction {mu}: seed {k + 1} of {seeds} done", file=sys.stderr)
        keys = ("ke_mj", "rot_mj", "up", "vz", "vh", "p10", "p50", "p90")
        fmt = {"ke_mj": "{:.4f}", "rot_mj": "{:.4f}", "up": "{:.4f}", "vz": "{:.2f}", "vh": "{:.2f}", "p10": "{:.2f}", "p50": "{:.2f}", "p90": "{:.2f}"}
        print(f"central region ({1e3 * MARGIN:g} mm in from each side), {seeds} seeds of each code; "
              "pooled value (per-seed standard deviation)")
        print()
        print("| friction | time us | code | shots in region | KE per shot mJ | spin energy per shot mJ | moving up | mean vz m/s | mean horizontal speed m/s "
              "| speed p10 / p50 / p90 m/s | KS distance of vz: codes (own seeds' halves) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        for mu in (0.0, 0.3):
            for s in steps:
                pooled = {}
                for code in ["LIGGGHTS"] + [c for c, _ in peenflow_codes(mu)]:
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
                        dist = f"{ks([p[5] for p in pooled['LIGGGHTS']], [p[5] for p in pooled[code]]):.3f} ({own:.3f})"
                    print(f"| {mu} | {s * DT_NS * 1e-3:g} | {code} | {st['n'] / seeds:.0f} | {cell('ke_mj')} | {cell('rot_mj')} | {cell('up')} | "
                          f"{cell('vz')} | {cell('vh')} | {st['p10']:.2f} / {st['p50']:.2f} / {st['p90']:.2f} | {dist} |")
                sys.stdout.flush()
        print()
        print(f"Impacts on the wall in the central region over {END_STEP * DT_NS * 1e-3:g} us (per seed, with the "
              "per-seed standard deviation; speeds pooled over the seeds)")
        print()
        print("| friction | code | impacts | first hits | mean normal speed m/s | normal speed p10 / p50 / p90 m/s "
              "| mean tangential speed m/s | mean surface spin speed omega R m/s | share at normal speed <10 / 10-30 / 30-50 / 50-69.9 / 69.9-70.1 / >70.1 m/s, % "
              "| impacts per 20 us | KS distance of normal speeds: codes (own seeds' halves) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        bands = ((0, 10), (10, 30), (30, 50), (50, 69.9), (69.9, 70.1), (70.1, math.inf))
        for mu in (0.0, 0.3):
            for code in ["LIGGGHTS"] + [c for c, _ in peenflow_codes(mu)]:
                per = impacts[(mu, code)]
                pooled = [p for imps in per for p in imps]
                vn = sorted(p[3] for p in pooled)
                n = len(vn)
                count = [len(imps) for imps in per]
                first = [sum(1 for p in imps if p[5]) for imps in per]
                mean_vn = [sum(p[3] for p in imps) / len(imps) for imps in per]
                share = " / ".join(f"{100 * sum(1 for v in vn if lo <= v < hi) / n:.1f}" for lo, hi in bands)
                bins = [0] * (END_STEP * DT_NS // 20000 + 1)
                for p in pooled:
                    bins[min(len(bins) - 1, int(p[0] / 20e-6))] += 1
                half = seeds // 2
                own = ks([p[3] for imps in per[:half] for p in imps], [p[3] for imps in per[half:] for p in imps])
                other = [p[3] for imps in impacts[(mu, "LIGGGHTS")] for p in imps]
                dist = f"({own:.3f})" if code == "LIGGGHTS" else f"{ks(other, vn):.3f} ({own:.3f})"
                print(f"| {mu} | {code} | {statistics.mean(count):.0f} ({statistics.stdev(count):.0f}) | "
                      f"{statistics.mean(first):.0f} ({statistics.stdev(first):.0f}) | "
                      f"{sum(vn) / n:.2f} ({statistics.stdev(mean_vn):.2f}) | "
                      f"{vn[n // 10]:.2f} / {vn[n // 2]:.2f} / {vn[9 * n // 10]:.2f} | "
                      f"{sum(p[4] for p in pooled) / n:.2f} | {sum(p[6] for p in pooled) / n:.2f} | {share} | {', '.join(str(round(b / seeds)) for b in bins)} | {dist} |")


if __name__ == "__main__":
    main()
