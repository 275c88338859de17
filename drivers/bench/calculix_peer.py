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
    forces, by CalculiX's projection on the *FREQUENCY modes: --ccx-modes
    asks for more of them than --modes, one CalculiX run per count; with
    as many as --modes a slender part's basis may hold no axial shape and
    the Coriolis coupling of in-plane bending is lost, doc/benchmarks.md);
  * by `cms modes` on the same mesh: the truth (Full basis, sparse Anasazi
    path; --no-truth skips it) and each --reductions entry (default a
    Craig-Bampton reduction with --vectors fixed-interface modes);
  * with --cms-lagrange (the bar), by `cms modes` on meshes of its own:
    Lagrange bricks of order 3 or 4 (Hex64, Hex125; no .inp element has
    their nodes, so CalculiX cannot run them), as coarse as the accuracy
    allows, graded towards the clamped root: a user's fastest route to the
    same accuracy, compared with CalculiX's on its C3D20 mesh.

Every frequency is compared with the cms truth of the same mesh and, given
--reference (the cms truth of a finer bar mesh, 'h:ns') or --reference-csv
(a cms modes CSV), with that reference. --repeat N runs every solver N
times, in turn (interleaved, so a change of machine load hits all alike),
and reports the medians.

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
    /usr/bin/python3 drivers/bench/calculix_peer.py --cms build/drivers/cms --model=bar --element=C3D20 \\
        --h=0.01 --ns=3 --omega=100 --modes=10 --ccx-modes=10,20 --reductions=Admissible:24,Craig-Bampton:30 \\
        --reference=0.0025:4 --repeat=3 --csv=bar-equal-accuracy.csv
    /usr/bin/python3 drivers/bench/calculix_peer.py --cms build/drivers/cms --model=bar --element=C3D20 \\
        --h=0.01 --ns=3 --omega=100 --modes=10 --ccx-modes=10 --no-truth --reductions=Admissible:24 \\
        --cms-lagrange=3:1:24:1.15,4:1:12:1.2 --reference-csv=doc/bench/bar-reference-400x6x6-2026-11-25.csv \\
        --repeat=3 --csv=bar-lagrange.csv
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


def write_deck(work, omega, modes, freq_modes, name="blade_ccx"):
    """The CalculiX deck: prestress, *FREQUENCY with freq_modes modes (the
    basis CalculiX projects the Coriolis forces on), *COMPLEX FREQUENCY with
    the lowest `modes` of them."""
    w2 = omega * omega
    load = f"blade, CENTRIF, {w2:.10g}, {AXIS_POINT[0]}, {AXIS_POINT[1]}, {AXIS_POINT[2]}, 0., 0., 1.\n"
    with open(os.path.join(work, name + ".inp"), "w") as f:
        f.write("*INCLUDE, INPUT=mesh.inp\n*MATERIAL, NAME=STEEL\n*ELASTIC\n"
                f"{E:.10g}, {NU}\n*DENSITY\n{RHO}\n*SOLID SECTION, ELSET=blade, MATERIAL=STEEL\n"
                "*BOUNDARY\nroot, 1, 3\n"
                "*STEP\n*STATIC\n*DLOAD\n" + load + "*END STEP\n"
                f"*STEP, PERTURBATION\n*FREQUENCY, STORAGE=YES\n{max(modes, freq_modes)}\n*DLOAD\n" + load + "*END STEP\n"
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


def write_scene(work, omega, modes, basis, vectors, target=0.0, tag=None, mesh="mesh.inp"):
    if basis == "Partitioned":  # vectors is "CUTOFF" or "CUTOFFxPARTS" (theory 18)
        cutoff, _, parts = str(vectors).partition("x")
        reduction = (f"      Reduction:\n        Basis: Partitioned\n        Cutoff Frequency: {float(cutoff)}\n" +
                     (f"        Partition: {{Parts: {int(parts)}}}\n" if parts else ""))
    else:
        reduction = f"      Reduction:\n        Basis: {basis}\n" + (f"        Vectors: {vectors}\n" if vectors else "")
    solver = "Sparse" if basis == "Full" else "Auto"
    tag = tag or basis
    path = os.path.join(work, f"blade-{tag}.yaml")
    with open(path, "w") as f:
        f.write(f"""Scene:
  Name: blade-{tag}
  Substructures:
    blade:
      Kind: C
      Spin:
        Axis: [0.0, 0.0, 1.0]
        Origin: [{AXIS_POINT[0]}, {AXIS_POINT[1]}, {AXIS_POINT[2]}]
        Rate: {omega}
      Finite Element Model:
        Mesh: {mesh}
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
""" + (f"    Target Accuracy: {target}\n" if target else ""))
    return path


def read_cms(work, tag):
    """(frequencies Hz, phase timings s from the JSON; with the physical DOFs
    of the run's mesh under "dofs")."""
    out = os.path.join(work, f"out-{tag}")
    with open(os.path.join(out, f"blade-{tag}-modes.csv")) as f:
        hz = [float(r["hz"]) for r in csv.DictReader(f)]
    phases = {}
    try:
        import json
        with open(os.path.join(out, f"blade-{tag}.json")) as f:
            d = json.load(f)
        phases = dict(d.get("timings_s", {}))
        phases["dofs"] = sum(s.get("physical_dofs", 0) for s in d.get("substructures", []))
    except (OSError, ValueError):
        pass
    return hz, phases


def parse_lagrange(text):
    """--cms-lagrange: [(order, ns, nx, grade)] from 'ORDER:NS:NX[:GRADE],...'."""
    out = []
    for item in filter(None, text.split(",")):
        parts = item.split(":")
        if len(parts) not in (3, 4):
            raise ValueError(f"--cms-lagrange: '{item}' is not ORDER:NS:NX[:GRADE]")
        order, ns, nx = (int(p) for p in parts[:3])
        grade = float(parts[3]) if len(parts) == 4 else 1.0
        if order not in (3, 4) or ns < 1 or nx < 1 or not grade >= 1.0:
            raise ValueError(f"--cms-lagrange: '{item}': order 3 or 4, ns and nx >= 1, grade >= 1")
        out.append((order, ns, nx, grade))
    return out


def write_lagrange_mesh(work, order, ns, nx, grade):
    """The bar in Lagrange bricks of `order` 3 or 4 (bar.geo: 64 or 125
    nodes), ns across, nx along growing by `grade` from the root: a mesh for
    cms alone (no .inp element has these nodes). Returns its file name in
    work."""
    name = f"bar-lagrange{order}-ns{ns}-nx{nx}-g{grade:g}.msh"
    cmd = ["gmsh", "-3", "-setnumber", "L", str(BAR_L), "-setnumber", "a", str(BAR_A), "-setnumber", "nx", str(nx),
           "-setnumber", "ns", str(ns), "-setnumber", "hex", "1", "-setnumber", "order", str(order),
           "-setnumber", "grade", str(grade), BAR_GEO, "-o", os.path.join(work, name)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return name


def parse_reductions(text, vectors):
    """'Craig-Bampton:30,Admissible:40,Admissible:ta=1e-3,Partitioned:2000x8' -> [(basis, vectors, target)]
    (Partitioned: its cut-off in Hz, optionally x the number of parts, kept as text)."""
    out = []
    for item in filter(None, text.split(",")):
        basis, _, arg = item.partition(":")
        if basis not in ("Craig-Bampton", "Admissible", "Modes", "Partitioned"):
            raise ValueError(f"--reductions: unknown basis '{basis}'")
        if basis == "Partitioned":
            if not re.fullmatch(r"[0-9.]+(x[0-9]+)?", arg):
                raise ValueError(f"--reductions: Partitioned needs CUTOFF or CUTOFFxPARTS, not '{arg}'")
            out.append((basis, arg, 0.0))
        elif arg.startswith("ta="):
            out.append((basis, 0, float(arg[3:])))
        else:
            out.append((basis, int(arg) if arg else vectors, 0.0))
    return out


def relative_errors(hz, ref):
    """Each frequency against the nearest reference frequency when the counts
    differ (CalculiX's complex step may drop one of a near-degenerate pair),
    else in order. Returns the list of relative differences."""
    if len(hz) == len(ref) and all(abs(f / r - 1) < 0.1 for f, r in zip(hz, ref)):
        match = list(range(len(hz)))
    else:
        match = [min(range(len(ref)), key=lambda j: abs(ref[j] - f)) for f in hz]
    return [hz[i] / ref[match[i]] - 1 for i in range(len(hz))]


def within(hz, ref):
    """The frequencies up to 5% above the reference's highest (CalculiX's
    complex step, missing modes, returns some above the range asked)."""
    return [f for f in hz if f <= 1.05 * max(ref)] if ref else hz


def median(xs):
    xs = sorted(x for x in xs if x is not None)
    return xs[len(xs) // 2] if xs else None


def free_dofs(work):
    """3 x (nodes of mesh.inp) - 3 x (nodes of the root set): the free DOFs."""
    nodes, root, section = 0, set(), None
    with open(os.path.join(work, "mesh.inp")) as f:
        for line in f:
            if line.startswith("*"):
                u = line.upper().replace(" ", "")
                section = "node" if u.startswith("*NODE") and "NSET=" not in u.split(",")[0] else \
                    ("root" if u.startswith("*NSET") and "NSET=ROOT" in u else None)
                continue
            if section == "node" and line.strip():
                nodes += 1
            elif section == "root":
                root.update(int(w) for w in line.replace(",", " ").split())
    return 3 * (nodes - len(root))


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
    ap.add_argument("--ccx-modes", default="",
                    help="comma-separated counts of CalculiX *FREQUENCY modes, the basis its Coriolis step projects "
                         "on (one CalculiX run each; default: --modes)")
    ap.add_argument("--reductions", default="",
                    help="cms reductions, comma-separated Basis:vectors or Basis:ta=accuracy (Target Accuracy) or "
                         "Partitioned:CUTOFF_HZ[xPARTS], "
                         "e.g. Craig-Bampton:30,Admissible:40,Admissible:ta=1e-3 (default: Craig-Bampton:--vectors)")
    ap.add_argument("--cms-lagrange", default="",
                    help="--model=bar: also run cms on its own meshes of Lagrange bricks, comma-separated "
                         "ORDER:NS:NX[:GRADE] (order 3: Hex64, 4: Hex125; NS across, NX along growing by GRADE "
                         "from the root), each with the first --reductions entry: equal accuracy on fewer DOFs, "
                         "against CalculiX on the C3D20 mesh of --h")
    ap.add_argument("--no-truth", action="store_true", help="skip the cms truth (Full basis) on each mesh")
    ap.add_argument("--reference", default="",
                    help="--model=bar: 'h:ns' of a finer mesh whose cms truth is the reference every row is compared "
                         "with (its own error is the difference between successive refinements: say it)")
    ap.add_argument("--reference-csv", default="", help="a cms modes CSV (column hz) to use as the reference")
    ap.add_argument("--repeat", type=int, default=1,
                    help="rounds of runs, every solver once per round in turn (interleaved); wall time and peak "
                         "memory are the medians")
    ap.add_argument("--threads", choices=("1", "default"), default="1",
                    help="1 (default): both tools on one thread (OMP_NUM_THREADS=OPENBLAS_NUM_THREADS=1, the "
                         "protocol of issue 18); default: each tool as it runs out of the box, on every core")
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
    try:
        reductions = parse_reductions(a.reductions or f"Craig-Bampton:{a.vectors}", a.vectors)
        ccx_modes = [int(w) for w in a.ccx_modes.split(",") if w] or [a.modes]
        lagrange = parse_lagrange(a.cms_lagrange)
    except ValueError as e:
        print(f"calculix_peer: {e}", file=sys.stderr)
        return 2
    a.cms = os.path.abspath(a.cms)
    if not os.access(a.cms, os.X_OK):
        print(f"calculix_peer: --cms {a.cms}: not an executable", file=sys.stderr)
        return 2
    ccx = shutil.which("ccx")
    if not ccx:
        print("calculix_peer: ccx not found (apt-get install calculix-ccx): the CalculiX rows are skipped")
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1") if a.threads == "1" else None

    reference, ref_label = None, ""
    if a.reference_csv:
        with open(a.reference_csv) as f:
            reference = [float(r["hz"]) for r in csv.DictReader(f)]
        ref_label = a.reference_csv
    elif a.reference:
        if a.model != "bar":
            print("calculix_peer: --reference needs --model=bar", file=sys.stderr)
            return 2
        rh, _, rns = a.reference.partition(":")
        ra = argparse.Namespace(**vars(a))
        ra.ns = int(rns or a.ns)
        work = os.path.abspath(os.path.join(a.work, f"reference-{a.element}-h{rh}-ns{ra.ns}"))
        os.makedirs(work, exist_ok=True)
        write_mesh(ra, float(rh), work)
        scene = write_scene(work, a.omega, a.modes, "Full", 0)
        s, mem, text = timed([a.cms, "modes", scene, f"--output={work}/out-Full"], work, env)
        reference = read_cms(work, "Full")[0]
        ref_label = f"cms truth, h = {rh}, ns = {ra.ns} ({free_dofs(work)} DOFs, {s:.1f} s, {mem or 0:.0f} MiB)"
        print(f"reference: {ref_label}")

    rows = []
    for h in sizes:
        work = os.path.abspath(os.path.join(a.work, f"h{h}" if a.model == "blade" else f"bar-{a.element}-h{h}-ns{a.ns}"))
        os.makedirs(work, exist_ok=True)
        element = write_mesh(a, h, work)
        dofs = free_dofs(work)
        # Every run: (label, command, reader of its frequencies -> [(label, hz, phases)]).
        runs = []
        if ccx:
            for n in filter(None, ccx_modes):  # 0: no CalculiX run
                name = f"blade_ccx{n}"
                write_deck(work, a.omega, a.modes, n, name)
                runs.append((f"ccx{n}", [ccx, "-i", name], name))
        for basis, vectors, target in ([("Full", 0, 0.0)] if not a.no_truth else []) + reductions:
            tag = basis if basis == "Full" else (f"{basis}-{vectors}" + (f"-ta{target:g}" if target else ""))
            scene = write_scene(work, a.omega, a.modes, basis, vectors, target, tag)
            runs.append((tag, [a.cms, "modes", scene, f"--output={work}/out-{tag}"], None))
        if lagrange and a.model != "bar":
            print("calculix_peer: --cms-lagrange needs --model=bar", file=sys.stderr)
            return 2
        for order, ns, nx, grade in lagrange:
            basis, vectors, target = reductions[0]
            mesh = write_lagrange_mesh(work, order, ns, nx, grade)
            tag = f"Hex{(order + 1) ** 3}-{ns}x{nx}-g{grade:g}-{basis}-{vectors}"
            scene = write_scene(work, a.omega, a.modes, basis, vectors, target, tag, mesh=mesh)
            runs.append((tag, [a.cms, "modes", scene, f"--output={work}/out-{tag}"], None))
        results = {}  # label -> {"s": [...], "mem": [...], "hz": [...], "phases": [...]}
        for r in range(a.repeat):
            for tag, cmd, ccx_name in runs:
                s, mem, text = timed(cmd, work, env)
                if ccx_name:
                    real, cplx = read_ccx(os.path.join(work, ccx_name + ".dat"))
                    n = tag[3:]
                    outs = [(f"CalculiX *FREQUENCY {n} modes (no Coriolis)", real[:a.modes], {}),
                            (f"CalculiX *COMPLEX FREQUENCY, CORIOLIS on {n} modes", cplx, {})]
                else:
                    hz, phases = read_cms(work, tag)
                    label = "cms truth (Full, sparse Anasazi)" if tag == "Full" else f"cms {tag}"
                    if tag.startswith("Hex"):
                        label += f" ({phases.get('dofs', 0)} DOFs)"
                    outs = [(label, hz, phases)]
                for label, hz, phases in outs:
                    e = results.setdefault(label, {"s": [], "mem": [], "hz": hz, "phases": []})
                    e["s"].append(s)
                    e["mem"].append(mem)
                    e["phases"].append(phases)
        truth = results.get("cms truth (Full, sparse Anasazi)", {}).get("hz")
        ccx_s = median(next((e["s"] for k, e in results.items() if k.startswith("CalculiX *COMPLEX")), [None]))
        print(f"\n{a.model} {element}, h = {h} m, ns = {a.ns}: {dofs} DOFs, spin {a.omega} rad/s, lowest {a.modes} modes,"
              f" median of {a.repeat} interleaved run(s); threads: {a.threads}; load {os.getloadavg()[0]:.2f}")
        if reference:
            print(f"reference: {ref_label}")
        print(f"{'solver':52s} {'wall s':>8s} {'peak MiB':>9s} {'f1 Hz':>10s} {'vs truth':>9s} {'vs ref.':>9s}"
              f" {'s / ccx':>8s}")
        for label, e in results.items():
            hz = within(e["hz"][:a.modes], reference or truth)
            d_truth = max(map(abs, relative_errors(hz, truth))) if truth and hz else float("nan")
            errs = relative_errors(hz, reference[:a.modes]) if reference and hz else []
            d_ref = max(map(abs, errs)) if errs else float("nan")
            s, mem = median(e["s"]), median(e["mem"])
            note = "" if len(hz) == a.modes else f"  ({len(hz)} of the {a.modes} modes, each matched to the nearest)"
            ratio = s / ccx_s if ccx_s else float("nan")
            print(f"{label:52s} {s:8.2f} {mem if mem else float('nan'):9.0f} {hz[0] if hz else float('nan'):10.5f}"
                  f" {d_truth:9.2e} {d_ref:9.2e} {ratio:8.2f}{note}")
            phases = {k: median([p.get(k) for p in e["phases"]]) for k in (e["phases"][0] if e["phases"] else {})
                      if k != "dofs"}
            for i in range(len(hz)):
                rows.append({"model": a.model, "element": element, "h": h, "ns": a.ns, "dofs": dofs,
                             "omega_rad_s": a.omega, "solver": label, "modes_returned": len(hz), "runs": len(e["s"]),
                             "wall_s": f"{s:.3f}", "wall_s_all": " ".join(f"{x:.3f}" for x in e["s"]),
                             "peak_mib": f"{mem:.1f}" if mem else "", "mode": i + 1, "hz": f"{hz[i]:.9g}",
                             "rel_diff_vs_cms_truth": f"{relative_errors(hz, truth)[i]:.3e}" if truth else "",
                             "rel_err_vs_reference": f"{errs[i]:.3e}" if errs else "",
                             "phases_s": " ".join(f"{k}={v:.3f}" for k, v in phases.items() if v is not None),
                             "threads": a.threads})
        if not ccx:
            rows.append({"model": a.model, "element": element, "h": h, "ns": a.ns, "dofs": dofs,
                         "solver": "CalculiX: skipped (ccx not found)"})
    with open(a.csv + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["model", "element", "h", "ns", "dofs", "omega_rad_s", "solver", "modes_returned", "runs",
                                          "wall_s", "wall_s_all", "peak_mib", "mode", "hz", "rel_diff_vs_cms_truth",
                                          "rel_err_vs_reference", "phases_s", "threads"])
        w.writeheader()
        w.writerows(rows)
    os.replace(a.csv + ".tmp", a.csv)
    print(f"\nwrote {a.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
