"""Checks a peenflow Abaqus .inp: every *INITIAL CONDITIONS, TYPE=VELOCITY data line is
exactly `node-or-set, dof, value` (a fourth field makes Abaqus silently take the wrong
one), dofs are 1-3, sets named there exist; and an independent mesh read (meshio) finds
the expected numbers of nodes and hexahedra.
usage: check_abaqus.py DECK NODES ELEMENTS SHOTS"""
import re
import sys

import meshio

path, n_nodes, n_elems, n_shots = sys.argv[1], *map(int, sys.argv[2:5])
text = open(path).read()
lines = text.splitlines()
nsets = set(m.group(1).upper() for m in re.finditer(r"(?im)^\*NSET,\s*NSET=([^,\s]+)", text))
i = 0
vel_lines = 0
while i < len(lines):
    if re.match(r"(?i)^\*INITIAL CONDITIONS,\s*TYPE=VELOCITY\s*$", lines[i]):
        i += 1
        while i < len(lines) and not lines[i].startswith("*"):
            fields = [f.strip() for f in lines[i].split(",")]
            assert len(fields) == 3, f"line {i + 1}: {lines[i]!r}"
            assert fields[0].upper() in nsets or fields[0].isdigit(), fields[0]
            assert fields[1] in ("1", "2", "3"), fields[1]
            float(fields[2])
            vel_lines += 1
            i += 1
    else:
        i += 1
assert vel_lines == 3 * n_shots, vel_lines
assert text.count("*NODE,") + text.count("*NODE\n") == 1, "nodes must be in one *NODE block"
mesh = meshio.read(path, file_format="abaqus")
assert len(mesh.points) == n_nodes, (len(mesh.points), n_nodes)
hexes = sum(len(c.data) for c in mesh.cells if c.type == "hexahedron")
assert hexes == n_elems, (hexes, n_elems)
print("ok", vel_lines, "velocity lines")
