#!/usr/bin/env python3
"""Calibrates peenflow's shot-specimen restitution and dent size with CalculiX: the
curves of `[restitution] shot_specimen_curve` and of `peenflow coverage --dent-curve`
(docs/fe-coupling.md, "Restitution and dent size from CalculiX").

For each normal impact speed it runs peenflow on one shot dropped onto the specimen (no
air, no gravity), exports that impact as a CalculiX deck (`peenflow export --format
calculix`), runs `ccx` on it and measures
  * the restitution, from the shot's kinetic energy before and after the contact
    (`e = sqrt(KE_end / KE_0)`);
  * the permanent dent: the radius of its rim, where the target's top surface, at the
    end, rises back through its original height (pile-up beyond), along the row of
    surface nodes nearest the impact (the grid is centred on it), both ways, averaged;
    and the depth at the nodes nearest the centre.
It prints a table, the deck's energy balance, the TOML line for a scene and the
`--dent-curve` argument (dent radius over shot radius).

Needs ccx (Debian: calculix-ccx). Each speed takes 10-60 s on two cores.

  python3 bench/fe_calibrate.py --binary target/release/peenflow \\
      --target-material A5052 --speeds 20,35,50,70,100
"""

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time


def kinetic_energies(dat):
    """The SHOTS set's kinetic energies (mJ) in calculix.dat, in time order."""
    lines = open(dat).read().splitlines()
    out = []
    for i, line in enumerate(lines):
        if "total kinetic energy for set SHOTS" in line:
            for nxt in lines[i + 1 : i + 4]:
                if nxt.strip():
                    out.append(float(nxt.split()[0]))
                    break
    return out


def dent(deck):
    """(rim radius mm, depth mm) of the permanent dent at the end of the run (the impact
    at x = y = 0 of the deck's frame, the top surface at z = 0)."""
    lines = open(os.path.join(deck, "calculix.inp")).read().splitlines()
    i = lines.index("*NODE, NSET=NALL") + 1
    nodes = {}
    while not lines[i].startswith("*"):
        f = lines[i].split(",")
        nodes[int(f[0])] = (float(f[1]), float(f[2]), float(f[3]))
        i += 1
    frd = open(os.path.join(deck, "calculix.frd")).read().splitlines()
    k = [j for j, l in enumerate(frd) if l.startswith(" -4  DISP")][-1] + 1
    while frd[k].startswith(" -5"):
        k += 1
    uz = {}
    while frd[k].startswith(" -1"):
        line = frd[k]
        uz[int(line[3:13])] = float(line[37:49])
        k += 1
    top = [(x, y, uz[n]) for n, (x, y, z) in nodes.items() if abs(z) < 1e-9 and n in uz]
    y0 = min(abs(y) for _, y, _ in top)
    rims = []
    for side in (1, -1):
        row = [(x, u) for x, y, u in top if abs(y - side * y0) < 1e-9]
        for sign in (1, -1):
            prof = sorted((sign * x, u) for x, u in row if sign * x > 0)
            for (x0, u0), (x1, u1) in zip(prof, prof[1:]):
                if u0 < 0 <= u1:
                    rims.append(math.hypot(x0 + (x1 - x0) * -u0 / (u1 - u0), y0))
                    break
    if not rims:
        return float("nan"), float("nan")
    return sum(rims) / len(rims), -min(u for *_, u in top)


def balance(log):
    """ccx's last printed energy balance, %, if any."""
    found = re.findall(r"energy balance \(relative\) = *([-+0-9.Ee]+) *%", open(log).read())
    return float(found[-1]) if found else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", default="target/release/peenflow")
    ap.add_argument("--speeds", default="20,35,50,70,100", help="m/s, comma-separated")
    ap.add_argument("--diameter-mm", type=float, default=0.8)
    ap.add_argument("--shot-material", default="table2-steel")
    ap.add_argument("--target-material", default="A5052")
    ap.add_argument("--elastic", action="store_true", help="elastic meshed shots")
    ap.add_argument("--element-size-mm", type=float,
                    help="target element size under the impact (export's default: shot radius / 4)")
    ap.add_argument("--shot-cells", type=int,
                    help="shot mesh cells per cube edge (export's default: 4 rigid, 6 elastic)")
    ap.add_argument("--keep", help="keep the runs and decks in this directory")
    a = ap.parse_args()
    if shutil.which("ccx") is None:
        sys.exit("fe_calibrate.py: ccx not found (Debian: apt-get install calculix-ccx)")
    binary = os.path.abspath(a.binary)
    speeds = [float(v) for v in a.speeds.split(",")]
    if any(v <= 0 for v in speeds) or speeds != sorted(set(speeds)):
        sys.exit("fe_calibrate.py: --speeds must be positive and increasing")
    work = a.keep or tempfile.mkdtemp(prefix="fe_calibrate_")
    os.makedirs(work, exist_ok=True)
    radius = 0.5 * a.diameter_mm
    rows = []
    for v in speeds:
        d = os.path.join(work, f"v{v:g}")
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "scene.toml"), "w") as f:
            f.write(
                f'title = "one {v:g} m/s impact"\n'
                "duration_ms = 0.05\ngravity_m_s2 = 0.0\n"
                "[effects]\ndrag = false\nlateral_force = false\n"
                f'[shots]\ndiameter_mm = {a.diameter_mm}\nmaterial = "{a.shot_material}"\n'
                f'[specimen]\nmaterial = "{a.target_material}"\n'
                '[shots.feed]\ntype = "list"\n[[shots.feed.shots]]\n'
                f"position_mm = [0.0, 0.0, {radius + 0.01}]\n"
                f"velocity_m_s = [0.0, 0.0, {-v}]\n"
            )
        for cmd in (
            [binary, "run", "scene.toml", "--out", "run", "--force"],
            [binary, "export", "run/impacts.h5", "--out", "deck", "--force",
             "--format", "calculix", "--target-material", a.target_material]
            + (["--elastic"] if a.elastic else [])
            + ([f"--element-size-mm={a.element_size_mm}"] if a.element_size_mm else [])
            + ([f"--shot-cells={a.shot_cells}"] if a.shot_cells else []),
        ):
            p = subprocess.run(cmd, cwd=d, capture_output=True, text=True)
            if p.returncode != 0:
                sys.exit(f"fe_calibrate.py: {' '.join(cmd)} failed:\n{p.stderr}")
        deck = os.path.join(d, "deck")
        t0 = time.time()
        with open(os.path.join(deck, "ccx.log"), "w") as log:
            p = subprocess.run(["ccx", "-i", "calculix"], cwd=deck, stdout=log,
                               stderr=subprocess.STDOUT,
                               env=dict(os.environ, OMP_NUM_THREADS="2"))
        if p.returncode != 0:
            sys.exit(f"fe_calibrate.py: ccx failed in {deck} (see ccx.log)")
        ke = kinetic_energies(os.path.join(deck, "calculix.dat"))
        if len(ke) < 2 or ke[0] <= 0:
            sys.exit(f"fe_calibrate.py: no kinetic energies in {deck}/calculix.dat")
        e = (ke[-1] / ke[0]) ** 0.5
        rim, depth = dent(deck)
        rows.append((v, e, balance(os.path.join(deck, "ccx.log")), time.time() - t0, rim, depth))
        print(f"{v:8g} m/s  e = {e:.4f}  dent rim radius {rim:.4f} mm (/R {rim / radius:.3f}), "
              f"depth {depth:.4f} mm  energy balance {rows[-1][2]:.2f} %  "
              f"ccx {rows[-1][3]:.0f} s", flush=True)
    mesh = ", ".join(
        x for x in (f"elements {a.element_size_mm:g} mm" if a.element_size_mm else "",
                    f"shot cells {a.shot_cells}" if a.shot_cells else "") if x) or "default mesh"
    print(f"\n# {a.diameter_mm:g} mm {a.shot_material} shot on {a.target_material}"
          f" ({'elastic' if a.elastic else 'rigid'} shot, {mesh}), CalculiX")
    print("[restitution]")
    print("shot_specimen_curve = { speed_m_s = [%s], restitution = [%s] }" % (
        ", ".join(f"{v:.1f}" for v, *_ in rows),
        ", ".join(f"{e:.3f}" for _, e, *_ in rows)))
    print("\n# peenflow coverage ... --dent-curve (speed m/s : dent radius / shot radius)")
    print("--dent-curve " + ",".join(f"{v:g}:{rim / radius:.3f}" for v, _, _, _, rim, _ in rows))
    if not a.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
