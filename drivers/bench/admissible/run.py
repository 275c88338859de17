#!/usr/bin/python3
"""Admissible vectors against Craig-Bampton per coordinate (issue 14 item 3).

Runs `cms compare` on the six scenes of this folder (a clamped beam, a thin
plate and a solid bar, each at rest and spinning in its own frame), one
after the other, keeps each `<case>-compare.csv`, and prints a markdown table
of the worst relative frequency error over the scene's lowest modes against
the truth model of the same mesh, for Admissible and Craig-Bampton at each
vector count per substructure, with the machine, the date and the commands.

    python3 drivers/bench/admissible/run.py                    # all six, into doc/bench/admissible/
    python3 drivers/bench/admissible/run.py --cases=beam-rest --out=/tmp/adm
    python3 drivers/bench/admissible/run.py --table-only       # the table from the CSVs already there

Debian's python3 only (no third-party modules). The table goes to stdout and
to <out>/table.md.
"""
import argparse
import csv
import datetime
import os
import platform
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
CASES = ["beam-rest", "beam-rotating", "plate-rest", "plate-rotating", "bar-rest", "bar-rotating"]
STRATEGIES = ["Admissible", "Craig-Bampton"]


def machine():
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    os_name = platform.platform()
    try:
        with open("/etc/os-release") as f:
            for line in f:
                if line.startswith("PRETTY_NAME="):
                    os_name = line.split("=", 1)[1].strip().strip('"')
    except OSError:
        pass
    return "%s, %d cores visible, %s" % (cpu, os.cpu_count() or 0, os_name)


def commit():
    try:
        out = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--", "packages"], capture_output=True,
                               text=True).stdout.strip()
        return out.stdout.strip() + (" (packages/ modified)" if dirty else "")
    except OSError:
        return "unknown"


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def fmt(x):
    return "%.1e" % x if x != 0 else "0"


def table(out, cases, counts, walls):
    lines = []
    head = "| case | truth DOFs | basis | " + " | ".join(str(k) for k in counts) + " | reduce s at %d | run s |" % counts[-1]
    lines.append(head)
    lines.append("|" + "---|" * (head.count("|") - 1))
    notes = []
    for case in cases:
        path = os.path.join(out, case + "-compare.csv")
        if not os.path.exists(path):
            lines.append("| %s | — | (not run) |" % case + " |" * (len(counts) + 2))
            continue
        rows = read_rows(path)
        by = {(r["strategy"], int(r["vectors_per_substructure"])): r for r in rows}
        truth = rows[0]["truth_dofs"]
        for s in STRATEGIES:
            cells = []
            for k in counts:
                r = by.get((s, k))
                if r is None:
                    cells.append("—")
                    continue
                cell = fmt(float(r["max_rel_error"]))
                other = by.get((STRATEGIES[1] if s == STRATEGIES[0] else STRATEGIES[0], k))
                if other is not None and other["reduced_dofs"] != r["reduced_dofs"]:
                    cell += " (%s DOFs)" % r["reduced_dofs"]
                cells.append(cell)
            last = by.get((s, counts[-1]))
            red = "%.2f" % float(last["reduce_s"]) if last else "—"
            wall = "%.0f" % walls[case] if case in walls and s == STRATEGIES[0] else ""
            lines.append("| %s | %s | %s | %s | %s | %s |" % (case if s == STRATEGIES[0] else "", truth if s ==
                         STRATEGIES[0] else "", s, " | ".join(cells), red, wall))
        dofs = sorted({(int(r["vectors_per_substructure"]), int(r["reduced_dofs"])) for r in rows
                       if r["strategy"] in STRATEGIES and int(r["vectors_per_substructure"]) in counts})
        notes.append(", ".join("%d" % d[1] for d in dofs))
    same = len(set(notes)) == 1
    notes = ["reduced DOFs at %s vectors: %s%s" % (", ".join(str(k) for k in counts), n,
             " in every case, for both bases" if same else " (%s)" % c) for n, c in
             (zip(notes[:1], cases[:1]) if same else zip(notes, cases))]
    return lines, notes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cms", default=os.path.join(ROOT, "build", "drivers", "cms"))
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--counts", default="6,8,12,16,20,24")
    ap.add_argument("--out", default=os.path.join(ROOT, "doc", "bench", "admissible"))
    ap.add_argument("--table-only", action="store_true")
    a = ap.parse_args()
    cases = a.cases.split(",")
    counts = [int(k) for k in a.counts.split(",")]
    os.makedirs(a.out, exist_ok=True)
    walls = {}
    commands = []
    for case in cases:
        scene = os.path.join(HERE, case + ".yaml")
        cmd = [a.cms, "compare", scene, "--counts=" + a.counts, "--output=" + a.out, "--no-plot"]
        shown = [a.cms, "compare", scene, "--counts=" + a.counts, "--output=" + os.path.abspath(a.out), "--no-plot"]
        commands.append(" ".join(c.replace(ROOT + os.sep, "") for c in shown))
        if a.table_only:
            continue
        t = time.time()
        p = subprocess.run(cmd, capture_output=True, text=True)
        walls[case] = time.time() - t
        with open(os.path.join(a.out, case + "-compare.log"), "w") as f:
            f.write(p.stdout + p.stderr)
        print("%s: exit %d, %.0f s" % (case, p.returncode, walls[case]), file=sys.stderr)
    if walls:
        with open(os.path.join(a.out, "walls.csv"), "w") as f:
            f.write("case,wall_s\n" + "".join("%s,%.1f\n" % kv for kv in walls.items()))
    elif os.path.exists(os.path.join(a.out, "walls.csv")):
        walls = {r["case"]: float(r["wall_s"]) for r in read_rows(os.path.join(a.out, "walls.csv"))}
    # Where and when the CSVs were made: recorded by the run, reused by --table-only.
    meta_path = os.path.join(a.out, "run.txt")
    if not a.table_only or not os.path.exists(meta_path):
        meta = "Machine: %s. Date: %s. Commit: %s." % (machine(), datetime.date.today().isoformat(), commit())
        with open(meta_path, "w") as f:
            f.write(meta + "\n")
    with open(meta_path) as f:
        meta = f.read().strip()
    lines, notes = table(a.out, cases, counts, walls)
    text = ["Worst relative frequency error over the lowest modes (each scene's \"Number of Modes\", 6) against the "
            "truth model of the same mesh, at each vector count per substructure (`cms compare`).",
            "",
            meta,
            "Commands (one after the other):",
            ""] + ["    " + c for c in commands] + [""] + lines + [""] + ["- " + n for n in notes]
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write("\n".join(text) + "\n")
    print("\n".join(text))


if __name__ == "__main__":
    main()
