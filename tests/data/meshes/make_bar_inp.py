#!/usr/bin/python3
# Usage (from the repository root): /usr/bin/python3 tests/data/meshes/make_bar_inp.py tests/data/meshes/bar_tet10.geo tests/data/meshes
"""Writes bar_tet10_short.msh (Gmsh; coordinates rounded to 14 digits) and bar_tet10_short.inp + bar_tet10_short_nodes.inp
(the same mesh in Gmsh's own Abaqus export: C3D10 in Abaqus node order), for
tests/unit/mesh/InpReaderTest.cpp and tests/mpi/InpSceneTest.cpp.
Node ids renumbered id -> 3 * (1000 - id) + 7 (sparse, order reversed), the
nodes in an *INCLUDE, the surface elements Gmsh writes for the physical
surfaces dropped (root and tip stay as node sets)."""
import subprocess, sys, os
geo, out = sys.argv[1], sys.argv[2]
msh = os.path.join(out, "bar_tet10_short.msh")
subprocess.run(["gmsh", "-3", "-setnumber", "L", "0.2", "-setnumber", "h", "0.02", "-format", "msh41", geo, "-o", msh],
               check=True, stdout=subprocess.DEVNULL)
# Coordinates rounded to the 14 significant digits Gmsh's Abaqus export
# writes, so that the .msh and the .inp hold the same numbers.
lines, at = open(msh).read().split("\n"), None
i = lines.index("$Nodes") + 1
blocks = int(lines[i].split()[0]); i += 1
for _ in range(blocks):
    n = int(lines[i].split()[3]); i += 1 + n
    for k in range(i, i + n):
        lines[k] = " ".join("%.14g" % float(v) for v in lines[k].split())
    i += n
open(msh, "w").write("\n".join(lines))
raw = os.path.join(out, "raw.inp")
subprocess.run(["gmsh", msh, "-0", "-setnumber", "Mesh.SaveGroupsOfNodes", "1", "-format", "inp", "-o", raw],
               check=True, stdout=subprocess.DEVNULL)
nid = lambda s: str(3 * (1000 - int(s)) + 7)
nodes, deck, section = [], [], None
for line in open(raw):
    line = line.rstrip("\n")
    if line.startswith("*"):
        u = line.upper().replace(" ", "")
        section = u.split(",")[0]
        if u.startswith("*HEADING") or u.startswith("*****"):
            section = "SKIP"; continue
        if section == "*ELEMENT" and "C3D10" not in u: section = "SKIP"; continue
        if section == "*ELSET" and ("=ROOT" in u or "=TIP" in u): section = "SKIP"; continue
        if section == "*NODE": continue
        deck.append(line); continue
    if section in ("SKIP", None) or line.strip() == "": continue
    f = [x.strip() for x in line.split(",")]
    if section == "*NODE":
        nodes.append(", ".join([nid(f[0])] + f[1:]))
    elif section == "*ELEMENT":
        deck.append(", ".join([f[0]] + [nid(x) for x in f[1:]]))
    elif section == "*NSET":
        deck.append(", ".join(nid(x) if x else "" for x in f))
    else:
        deck.append(line)
head = ("** The bar of bar_tet10.geo (L = 0.2, h = 0.02), Gmsh 4.8's Abaqus export of\n"
        "** bar_tet10_short.msh (tests/data/meshes/make_bar_inp.py): node ids\n"
        "** renumbered 3 (1000 - id) + 7, nodes in an included file.\n*HEADING\nbar\n"
        "*NODE, NSET=all\n*INCLUDE, INPUT=bar_tet10_short_nodes.inp\n")
open(os.path.join(out, "bar_tet10_short.inp"), "w").write(head + "\n".join(deck) + "\n")
open(os.path.join(out, "bar_tet10_short_nodes.inp"), "w").write("** nodes of bar_tet10_short.inp\n" + "\n".join(nodes) + "\n")
os.remove(raw)
