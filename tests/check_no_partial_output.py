#!/usr/bin/python3
"""A run that cannot write one of its files writes none of them.

usage: check_no_partial_output.py CMS CAMPBELL [MPIEXEC [SOLID_BLADE_SCENE]]

Found by a review: each file was renamed into place as soon as it was
written, and the mode shapes' streams were never checked, so
  - under a file-size limit (a full disk) `cms modes --vtu` renamed VTU
    files cut in the middle of their XML and exited 0, and a JSON that
    failed left the two CSVs written before it (and its .tmp);
  - a mode-shape file that could not be opened left the JSON, the CSVs
    and the earlier mode shapes behind, and on two ranks hung (rank 0
    threw, rank 1 waited in the next mode's gather);
  - the standalone `campbell --csv` wrote a CSV cut short and exited 0;
  - a .geo script's mesh cut short by the limit was blamed on the script
    ("cannot be read back") instead of the write;
  - a result whose name was taken by a directory failed to be renamed
    after the files before it had been: those were left, the run exited
    as an internal error, and two ranks hung.
Each case must now exit with a failure, name what failed, and leave the
output directory without a result or temporary file.
"""
import os
import resource
import signal
import subprocess
import sys
import tempfile

FAILED = []


def limited(limit):
    def apply():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write past the limit fails instead of killing
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return apply


def check(what, cmd, cwd, out, expect, preexec=None, allowed=()):
    try:
        r = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           preexec_fn=preexec, timeout=60)
    except subprocess.TimeoutExpired:
        FAILED.append(f"{what}: hung (killed after 60 s)")
        return None
    left = sorted(set(os.listdir(out)) - set(allowed)) if os.path.isdir(out) else []
    if r.returncode == 0:
        FAILED.append(f"{what}: exit 0\n{r.stdout}")
    elif expect not in r.stdout:
        FAILED.append(f"{what}: exit {r.returncode} without \"{expect}\"\n{r.stdout}")
    if left:
        FAILED.append(f"{what}: left {left} in {out}")
    print(f"{what}: exit {r.returncode}, {len(left)} file(s) left")
    return r.returncode


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    cms, campbell = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    mpiexec = sys.argv[3] if len(sys.argv) > 3 else None
    solid_blade = os.path.abspath(sys.argv[4]) if len(sys.argv) > 4 else None
    with tempfile.TemporaryDirectory() as d:
        # 1. A file-size limit below the JSON's size (16 kB) and the mode
        #    shapes' (8-12 kB), above the CSVs': the CSVs are written first.
        out = os.path.join(d, "limit")
        check("cms modes --vtu, file-size limit", [cms, "modes", "--vtu", "--output=" + out], d, out,
              "writing failed", limited(6000))
        # 2. A mode shape's temporary name taken by a directory.
        out = os.path.join(d, "blocked")
        os.makedirs(os.path.join(out, "spacecraft-mode-3.vtu.tmp"))
        check("cms modes --vtu, a file that cannot be opened", [cms, "modes", "--vtu", "--output=" + out], d, out,
              "spacecraft-mode-3.vtu: cannot write", allowed=["spacecraft-mode-3.vtu.tmp"])
        if mpiexec:
            out = os.path.join(d, "blocked2")
            os.makedirs(os.path.join(out, "spacecraft-mode-3.vtu.tmp"))
            check("2 ranks: cms modes --vtu, a file that cannot be opened",
                  [mpiexec, "-n", "2", cms, "modes", "--vtu", "--output=" + out], d, out,
                  "spacecraft-mode-3.vtu: cannot write", allowed=["spacecraft-mode-3.vtu.tmp"])
        # 3. A .geo scene meshed under a limit below its mesh's size: Gmsh's
        #    failed write was read as a malformed mesh (exit 2 blaming the
        #    script); it must say the mesh could not be written.
        if solid_blade:
            out = os.path.join(d, "geo")
            check("cms modes on a .geo scene, file-size limit", [cms, "modes", solid_blade, "--output=" + out], d,
                  out, "could not write the mesh", limited(100 * 1024))
        # 4. The standalone Campbell program's --csv under a limit.
        out = os.path.join(d, "campbell")
        os.makedirs(out)
        check("campbell --csv, file-size limit", [campbell, "--steps=13", "--csv=" + os.path.join(out, "c.csv")], d,
              out, "writing failed", limited(1024))
        # 5. A result's own name taken by a directory: every file written
        #    whole, then its rename fails. It renamed the files before it
        #    (partial output), exited 5 as an internal error, and on two
        #    ranks hung (rank 0 threw past the collective commit).
        for ranks in ([], [mpiexec, "-n", "2"] if mpiexec else None):
            if ranks is None:
                continue
            out = os.path.join(d, f"taken{len(ranks)}")
            os.makedirs(os.path.join(out, "spacecraft-coverage.csv", "x"))
            what = ("2 ranks: " if ranks else "") + "cms modes, a result's name taken by a directory"
            code = check(what, ranks + [cms, "modes", "--output=" + out], d, out,
                         "spacecraft-coverage.csv: cannot replace", allowed=["spacecraft-coverage.csv"])
            if code is not None and code != 2:
                FAILED.append(f"{what}: exit {code}, not 2 (a file that cannot be written)")
        # 6. A rename that fails after the checks: the earlier results a run
        #    replaces are kept aside and put back, not lost. The results of a
        #    first run, then a second whose setting aside of one of them is
        #    refused (its aside name taken by a directory).
        out = os.path.join(d, "again")
        first = subprocess.run([cms, "modes", "--output=" + out], cwd=d, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=60)
        if first.returncode != 0:
            FAILED.append(f"first run for case 6: exit {first.returncode}\n{first.stdout}")
        else:
            before = {f: open(os.path.join(out, f), "rb").read() for f in os.listdir(out)}
            os.makedirs(os.path.join(out, "spacecraft-modes.csv.replaced", "x"))
            r = subprocess.run([cms, "modes", "--truth", "--output=" + out], cwd=d,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
            after = {f: open(os.path.join(out, f), "rb").read() for f in os.listdir(out)
                     if f != "spacecraft-modes.csv.replaced"}
            if r.returncode != 2 or "cannot replace" not in r.stdout:
                FAILED.append(f"a failed replacement: exit {r.returncode}\n{r.stdout}")
            if after != before:
                FAILED.append(f"a failed replacement changed the earlier results: {sorted(before)} -> {sorted(after)}")
            print(f"cms modes, a failed replacement: exit {r.returncode}, earlier results "
                  f"{'kept' if after == before else 'changed'}")
    if FAILED:
        sys.exit("check_no_partial_output:\n" + "\n".join(FAILED))
    print("check_no_partial_output: no partial output")


if __name__ == "__main__":
    main()
