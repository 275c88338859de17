#!/usr/bin/python3
"""CalculiX side by side with this framework on one rotating blade (issues #6, #18).

Two models, both clamped at the root and spinning about the z axis through
(-0.1, 0, 0) (the root at the hub radius 0.1 m of rotor.yaml), steel:

  * --model=blade (default): the blade of the benchmark rotor
    (drivers/bench/rotor/blade.geo), 10-node tetrahedra of size h;
  * --model=bar: the slender solid bar of issue 18 (drivers/bench/bar.geo,
    L = 1 m, a 0.02 m square section), --element=C3D20 (20-node bricks, h
    along, --ns across each side; C3D20R for reduced integration) or C3D10
    (10-node tetrahedra of size h).

Each is solved:

  * by CalculiX (Debian's calculix-ccx): a linear *STATIC step with the
    CENTRIF load (the prestress), then *FREQUENCY with PERTURBATION (stress
    stiffening of the static step; the CENTRIF load of the step adds the
    centrifugal softening), then *COMPLEX FREQUENCY, CORIOLIS (the Coriolis
    forces, by CalculiX's projection on the *FREQUENCY modes);
  * by `cms modes` on the same mesh: the truth (Full basis, sparse Anasazi
    path) and a Craig-Bampton reduction (--vectors fixed-interface modes).

Both tools read the same Abaqus/CalculiX mesh deck, mesh.inp: Gmsh meshes the
.geo once and exports it (its Abaqus export: C3D10 or C3D20 elements, node
and element sets of the physical groups; the surface elements it also writes
are dropped); CalculiX *INCLUDEs it, the cms scene names it as its Mesh
(packages/mesh, readInp). Each run is timed with its peak memory (/usr/bin/time -v
where present; else wall time only). If ccx is absent the CalculiX rows are
skipped and say so. Output: a table and a CSV with the frequencies of every
solver and their relative differences.

    /usr/bin/python3 drivers/bench/calculix_peer.py --cms build/drivers/cms \\
        --h 0.02,0.01,0.006 --csv doc/bench/calculix-peer.csv
    /usr/bin/python3 drivers/bench/calculix_peer.py --cms build/drivers/cms --model=bar \\
        --element=C3D20 --h=0.02,0.01 --ns=1 --omega=100 --modes=10 --csv=bar-peer.csv
"""
import argparse
import csv
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
GEO = os.path.join(HERE, "rotor", "blade.geo")
BAR_GEO = os.path.join(HERE, "bar.geo")
BAR_L, BAR_A = 1.0, 0.02
E, NU, RHO = 2.1e11, 0.3, 7850.0
AXIS_POINT = (-0.1, 0.0, 0.0)


def timed(cmd, cwd, env=None):
    """Runs cmd; returns (seconds, peak MiB or None, stdout+stderr)."""
    gnu_time = shutil.which("time", path="/usr/bin")
    full = ([gnu_time, "-v"] if gnu_time else []) + cmd
    t0 = time.monotonic()
    p = subprocess.run(full, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.monotonic() - t0
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout[-3000:]}")
    peak = None
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stdout)
    if m:
        peak = int(m.group(1)) / 1024.0
    return seconds, peak, p.stdout


def write_mesh(a, h, work):
    """Meshes the model with Gmsh and writes mesh.inp (Gmsh's Abaqus export,
    solid elements and the node sets kept) for both tools. Returns the element
    type of the deck."""
    msh = os.path.join(work, "mesh.msh")
    if a.model == "blade":
        cmd, element = ["gmsh", "-3", "-setnumber", "h", str(h), GEO], "C3D10"
    else:
        nx = max(1, round(BAR_L / h))
        hexes = a.element != "C3D10"
        cmd = ["gmsh", "-3", "-setnumber", "L", str(BAR_L), "-setnumber", "a", str(BAR_A),
               "-setnumber", "nx", str(nx), "-setnumber", "ns", str(a.ns), "-setnumber", "hex", "1" if hexes else "0",
               BAR_GEO]
        element = a.element
    subprocess.run(cmd + ["-o", msh], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    raw = os.path.join(work, "mesh-raw.inp")
    subprocess.run(["gmsh", msh, "-0", "-setnumber", "Mesh.SaveGroupsOfNodes", "1", "-format", "inp", "-o", raw],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    # Keep the nodes, the solid elements and the node sets; drop the surface
    # elements Gmsh writes for the physical surfaces (and their element sets).
    solid = "C3D10" if element == "C3D10" else "C3D20"
    out, keep = [], True
    with open(raw) as f:
        for line in f:
            if line.startswith("*"):
                u = line.upper()
                keep = not (u.startswith("*ELEMENT") and solid not in u) and not u.startswith("*HEADING") \
                    and not u.startswith("******") \
                    and not (u.startswith("*ELSET") and ("ROOT" in u or "TIP" in u))
                if keep and u.startswith("*ELEMENT") and element == "C3D20R":
                    line = re.sub("C3D20", "C3D20R", line, flags=re.I)
            if keep:
                out.append(line)
    with open(os.path.join(work, "mesh.inp"), "w") as f:
        f.writelines(out)
    return element


def write_deck(work, omega, modes):
    w2 = omega * omega
    load = f"blade, CENTRIF, {w2:.10g}, {AXIS_POINT[0]}, {AXIS_POINT[1]}, {AXIS_POINT[2]}, 0., 0., 1.\n"
    with open(os.path.join(work, "blade_ccx.inp"), "w") as f:
        f.write("*INCLUDE, INPUT=mesh.inp\n*MATERIAL, NAME=STEEL\n*ELASTIC\n"
                f"{E:.10g}, {NU}\n*DENSITY\n{RHO}\n*SOLID SECTION, ELSET=blade, MATERIAL=STEEL\n"
                "*BOUNDARY\nroot, 1, 3\n"
                "*STEP\n*STATIC\n*DLOAD\n" + load + "*END STEP\n"
                f"*STEP, PERTURBATION\n*FREQUENCY, STORAGE=YES\n{modes}\n*DLOAD\n" + load + "*END STEP\n"
                f"*STEP, PERTURBATION\n*COMPLEX FREQUENCY, CORIOLIS\n{modes}\n*END STEP\n")


def read_ccx(dat):
    """(real eigenfrequencies Hz, complex-frequency step Hz) from the .dat."""
    blocks = open(dat).read().split("E I G E N V A L U E   O U T P U T")[1:]
    if len(blocks) < 2:
        raise RuntimeError(f"{dat}: no *FREQUENCY and *COMPLEX FREQUENCY output")
    def rows(block, col):
        out = []
        for line in block.split("\n"):
            parts = line.split()
            if len(parts) >= 4 and parts[0].isdigit():
                out.append(float(parts[col]))
            elif out and not parts:
                break
        return out
    return rows(blocks[0], 3), rows(blocks[1], 2)


def write_scene(work, omega, modes, basis, vectors):
    reduction = f"      Reduction:\n        Basis: {basis}\n" + (f"        Vectors: {vectors}\n" if vectors else "")
    solver = "Sparse" if basis == "Full" else "Auto"
    path = os.path.join(work, f"blade-{basis}.yaml")
    with open(path, "w") as f:
        f.write(f"""Scene:
  Name: blade-{basis}
  Substructures:
    blade:
      Kind: C
      Spin:
        Axis: [0.0, 0.0, 1.0]
        Origin: [{AXIS_POINT[0]}, {AXIS_POINT[1]}, {AXIS_POINT[2]}]
        Rate: {omega}
      Finite Element Model:
        Mesh: mesh.inp
        Materials:
          steel:
            Young's Modulus: {E}
            Poisson's Ratio: {NU}
            Density: {RHO}
        Element Sets:
          blade:
            Type: Solid
            Material: steel
        Boundary Conditions:
          root:
            Node Set: root
{reduction}  Analysis:
    Number of Modes: {modes}
    Solver: {solver}
""")
    return path


def read_cms(work, basis):
    with open(os.path.join(work, f"out-{basis}", f"blade-{basis}-modes.csv")) as f:
        return [float(r["hz"]) for r in csv.DictReader(f)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cms", required=True, help="the cms executable")
    ap.add_argument("--model", choices=("blade", "bar"), default="blade", help="the rotor's blade or issue 18's bar")
    ap.add_argument("--element", choices=("C3D20", "C3D20R", "C3D10"), default="C3D20", help="--model=bar: element type")
    ap.add_argument("--ns", type=int, default=1, help="--model=bar, bricks: elements across each side of the section")
    ap.add_argument("--h", default="0.02,0.01", help="comma-separated mesh sizes (m; the bar: element length)")
    ap.add_argument("--omega", type=float, default=200.0, help="spin rate (rad/s)")
    ap.add_argument("--modes", type=int, default=20)
    ap.add_argument("--vectors", type=int, default=30, help="Craig-Bampton fixed-interface modes")
    ap.add_argument("--work", default="calculix-peer", help="scratch directory")
    ap.add_argument("--csv", default="calculix-peer.csv")
    a = ap.parse_args()
    sizes = []
    for w in a.h.split(","):
        try:
            sizes.append(float(w))
        except ValueError:
            print(f"calculix_peer: --h: '{w}' is not a number", file=sys.stderr)
            return 2
    a.cms = os.path.abspath(a.cms)
    if not os.access(a.cms, os.X_OK):
        print(f"calculix_peer: --cms {a.cms}: not an executable", file=sys.stderr)
        return 2
    ccx = shutil.which("ccx")
    if not ccx:
        print("calculix_peer: ccx not found (apt-get install calculix-ccx): the CalculiX rows are skipped")
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    rows = []
    for h in sizes:
        work = os.path.abspath(os.path.join(a.work, f"h{h}" if a.model == "blade" else f"bar-{a.element}-h{h}"))
        os.makedirs(work, exist_ok=True)
        element = write_mesh(a, h, work)
        dofs = None
        runs = {}
        if ccx:
            write_deck(work, a.omega, a.modes)
            s, mem, _ = timed([ccx, "-i", "blade_ccx"], work, env)
            real, cplx = read_ccx(os.path.join(work, "blade_ccx.dat"))
            runs["CalculiX *FREQUENCY (no Coriolis)"] = (s, mem, real)
            runs["CalculiX *COMPLEX FREQUENCY, CORIOLIS"] = (s, mem, cplx)
        for basis, vectors in (("Full", 0), ("Craig-Bampton", a.vectors)):
            scene = write_scene(work, a.omega, a.modes, basis, vectors)
            s, mem, text = timed([a.cms, "modes", scene, f"--output={work}/out-{basis}"], work, env)
            m = re.search(r"blade\s+C\s+(\d+)", text)
            dofs = int(m.group(1)) if m else dofs
            label = "cms truth (Full, sparse Anasazi)" if basis == "Full" else f"cms Craig-Bampton {vectors}"
            runs[label] = (s, mem, read_cms(work, basis))
        ref_key = "cms truth (Full, sparse Anasazi)"
        ref = runs[ref_key][2]
        print(f"\n{a.model} {element}, h = {h} m: {dofs} DOFs, spin {a.omega} rad/s, lowest {a.modes} modes")
        print(f"{'solver':42s} {'wall s':>8s} {'peak MiB':>9s} {'f1 Hz':>10s} {'max |rel. diff| vs cms truth':>30s}")
        for label, (s, mem, hz) in runs.items():
            # CalculiX's complex step may return fewer modes than asked (it
            # drops some of a near-degenerate pair): each of its frequencies is
            # then compared with the nearest of the truth's, and the count said.
            if len(hz) == len(ref):
                match = list(range(len(hz)))
            else:
                match = [min(range(len(ref)), key=lambda j: abs(ref[j] - f)) for f in hz]
            n = len(hz)
            diff = max(abs(hz[i] / ref[match[i]] - 1) for i in range(n)) if n else float("nan")
            note = "" if len(hz) == len(ref) else f"  ({len(hz)} modes, each matched to the nearest)"
            print(f"{label:42s} {s:8.2f} {mem if mem else float('nan'):9.0f} {hz[0]:10.5f} {diff:30.2e}{note}")
            for i in range(n):
                rows.append({"model": a.model, "element": element, "h": h, "dofs": dofs, "solver": label, "wall_s": f"{s:.3f}",
                             "peak_mib": f"{mem:.1f}" if mem else "", "mode": i + 1, "hz": f"{hz[i]:.9g}",
                             "rel_diff_vs_cms_truth": f"{hz[i] / ref[match[i]] - 1:.3e}"})
        if not ccx:
            rows.append({"model": a.model, "element": element, "h": h, "dofs": dofs,
                         "solver": "CalculiX: skipped (ccx not found)"})
    with open(a.csv + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["model", "element", "h", "dofs", "solver", "wall_s", "peak_mib", "mode", "hz",
                                          "rel_diff_vs_cms_truth"])
        w.writeheader()
        w.writerows(rows)
    os.replace(a.csv + ".tmp", a.csv)
    print(f"\nwrote {a.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
