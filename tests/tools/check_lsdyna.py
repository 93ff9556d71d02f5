"""Structural checks of a peenflow LS-DYNA keyword deck with an independent keyword
reader (PyPI ansys-dyna-core), which is not a validator (it parses malformed cards into
raw keywords or wrong values silently), so the checks are our own:
every keyword parsed (no raw string keywords, no warnings); fixed columns (no line over
80 columns, no tabs; *NODE rows are 8+16+16+16+8+8 wide, *ELEMENT_SOLID rows 10x8);
no dangling part/section/material/node ids; counts of nodes, elements, parts and
initial velocities as given on the command line; with SPIN, the first shot's velocity
generation card spins at OMEGA rad/s about the axis (NX, NY, NZ) through its centre.
usage: check_lsdyna.py DECK NODES ELEMENTS SHOTS [OMEGA NX NY NZ]"""
import sys
import warnings

from ansys.dyna.core import Deck

path, n_nodes, n_elems, n_shots = sys.argv[1], *map(int, sys.argv[2:5])
text = open(path).read()
lines = text.splitlines()
assert all(len(l) <= 80 for l in lines), [l for l in lines if len(l) > 80][:3]
assert "\t" not in text
# Fixed columns in the bulk cards.
section = None
for l in lines:
    if l.startswith("*"):
        section = l.strip()
        continue
    if l.startswith("$"):
        continue
    if section == "*NODE":
        assert len(l) == 72, repr(l)
        int(l[0:8]); [float(l[8 + 16 * k: 24 + 16 * k]) for k in range(3)]
    if section == "*ELEMENT_SOLID":
        assert len(l) == 80, repr(l)
        [int(l[8 * k: 8 * k + 8]) for k in range(10)]
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    deck = Deck()
    deck.loads(text)
assert not caught, [str(w.message) for w in caught][:3]
kws = list(deck.keywords)
raw = [k for k in kws if isinstance(k, str)]
assert not raw, raw[:2]
by = {}
for k in kws:
    by.setdefault(type(k).__name__, []).append(k)
nodes = by["Node"][0].nodes
elems = by["ElementSolid"][0].elements
assert len(nodes) == n_nodes, (len(nodes), n_nodes)
assert len(elems) == n_elems, (len(elems), n_elems)
node_ids = set(nodes["nid"])
assert len(node_ids) == n_nodes
for c in ["n1", "n2", "n3", "n4", "n5", "n6", "n7", "n8"]:
    assert set(elems[c]) <= node_ids, f"element refers to a missing node ({c})"
parts = {int(p.parts["pid"][0]): p for p in by["Part"]}
assert len(parts) == n_shots + 1, parts.keys()
assert set(elems["pid"]) <= set(parts), "element refers to a missing part"
secids = {int(s.secid) for s in by["SectionSolid"]}
mids = set()
for name in ("MatRigid", "MatElastic", "MatPiecewiseLinearPlasticity"):
    for m in by.get(name, []):
        mids.add(int(m.mid))
for pid, p in parts.items():
    assert int(p.parts["secid"][0]) in secids, f"part {pid}: missing section"
    assert int(p.parts["mid"][0]) in mids, f"part {pid}: missing material"
vel = by.get("InitialVelocityGeneration", [])
assert len(vel) == n_shots, len(vel)
for v in vel:
    assert int(v.id) in parts and int(v.styp) == 2
if len(sys.argv) > 5:
    omega, *axis = map(float, sys.argv[5:9])
    v = vel[0]
    assert abs(v.omega - omega) <= 1e-6 * omega, (v.omega, omega)
    got = [v.nx, v.ny, v.nz]
    assert all(abs(a - b) <= 1e-6 for a, b in zip(got, axis)), (got, axis)
else:
    assert all(float(v.omega) == 0.0 for v in vel)
for c in by.get("ContactAutomaticSurfaceToSurface", []):
    assert int(c.surfa) in parts and int(c.surfb) in parts and int(c.surfatyp) == 3 == int(c.surfbtyp)
assert len(by.get("ContactAutomaticSurfaceToSurface", [])) == n_shots
assert "ControlTermination" in by
print("ok", len(kws), "keywords")
