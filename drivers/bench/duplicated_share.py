#!/usr/bin/env python3
"""The share of C++ lines that repeat elsewhere (issue 17: "duplicated lines
stay below 1%"), from the rows of the `duplicates` tool.

    duplicates --most 200 --seconds 120 > dups.txt
    python3 drivers/bench/duplicated_share.py dups.txt

Counted: every line of both sides of every row whose files are C++ (.cpp,
.hpp) under packages/, drivers/, tests/ or examples/, once per file however
many rows name it. A row's "(+N more runs)" are found here again: the
further runs of 6 or more lines that are the same to the letter (after the
tool's own folding: white space, blank lines, comments, lone punctuation and
#include lines passed over); a shape-only row's further runs are not
located by the tool and are not counted. Divided by all lines (wc -l) of
those C++ files that git tracks. Printed twice: every row, and without the
rows the tool marks boilerplate (thin shapes: punctuation, keywords, a
shape that recurs across a folder).
"""
import re
import subprocess
import sys
from pathlib import Path

ROOTS = ("packages/", "drivers/", "tests/", "examples/")
ROW = re.compile(r"^D\d+ (\S+):(\d+)-(\d+) ~ (\S+):(\d+)-(\d+)(.*)$")


def counted(path):
    return path.startswith(ROOTS) and path.endswith((".cpp", ".hpp"))


def folded(line):
    s = " ".join(line.split())
    if not s or s.startswith("//") or s.startswith("#include") or re.fullmatch(r"[{}()\[\];,]*", s):
        return None
    return s


def identical_runs(a, b, min_lines=6):
    """Maximal runs of >= min_lines folded lines that a and b share: (a lines, b lines)."""
    fa = [(i + 1, folded(l)) for i, l in enumerate(Path(a).read_text(errors="replace").splitlines())]
    fb = [(i + 1, folded(l)) for i, l in enumerate(Path(b).read_text(errors="replace").splitlines())]
    fa = [x for x in fa if x[1] is not None]
    fb = [x for x in fb if x[1] is not None]
    where = {}
    for j, (_, s) in enumerate(fb):
        where.setdefault(s, []).append(j)
    out_a, out_b = set(), set()
    length = {}
    for i, (_, s) in enumerate(fa):
        for j in where.get(s, ()):
            if a == b and j <= i:  # one file against itself: not a line against itself
                continue
            length[(i, j)] = length.get((i - 1, j - 1), 0) + 1
    for (i, j), n in length.items():
        if n >= min_lines and length.get((i + 1, j + 1), 0) == 0:  # a maximal run ends here
            out_a.update(range(fa[i - n + 1][0], fa[i][0] + 1))
            out_b.update(range(fb[j - n + 1][0], fb[j][0] + 1))
    return out_a, out_b


def share(rows, skip_boilerplate):
    dup = {}
    for row in rows:
        m = ROW.match(row)
        if not m:
            continue
        a, a0, a1, b, b0, b1, rest = m.groups()
        if skip_boilerplate and "boilerplate" in rest:
            continue
        for f, lo, hi in ((a, a0, a1), (b, b0, b1)):
            if counted(f):
                dup.setdefault(f, set()).update(range(int(lo), int(hi) + 1))
        if "more run" in rest and "shape" not in rest.split("(")[0]:
            ra, rb = identical_runs(a, b)
            if counted(a):
                dup.setdefault(a, set()).update(ra)
            if counted(b):
                dup.setdefault(b, set()).update(rb)
    return dup


def main():
    rows = Path(sys.argv[1]).read_text().splitlines()
    dup = share(rows, False)
    files = [f for f in subprocess.run(["git", "ls-files"] + list(ROOTS), capture_output=True, text=True,
                                        check=True).stdout.split() if counted(f)]
    total = sum(len(Path(f).read_text(errors="replace").splitlines()) for f in files)
    n = sum(len(v) for v in dup.values())
    for f in sorted(dup, key=lambda f: -len(dup[f])):
        print(f"{len(dup[f]):6d}  {f}")
    print(f"duplicated {n} of {total} lines of C++ in {len(files)} files: {100.0 * n / total:.2f}%")
    thin = sum(len(v) for v in share(rows, True).values())
    print(f"without the rows marked boilerplate: {thin} lines, {100.0 * thin / total:.2f}%")


if __name__ == "__main__":
    main()
