#!/usr/bin/python3
"""The cms launcher starts the engine once (drivers/cms/launcher.cpp).

usage: check_one_start.py LAUNCHER

Run with LD_DEBUG=files, a process's loader names every shared library it
maps, once per start. The engine run directly maps Trilinos's Tpetra twice
when its heap's tunable is missing (it executes itself again from its
.preinit_array, cms/core/HugePageHeap.hpp), once otherwise; through the
launcher, which passes the tunable, it must map it once whatever the
machine. The engine's own count is printed, to show what the launcher
saves here. Also: a launcher without the engine beside it fails with exit
code 5 and a message naming the engine, having started nothing; and it
maps glibc alone (its C++ runtime linked in, drivers/CMakeLists.txt).
"""
import os
import shutil
import subprocess
import sys
import tempfile


def tpetra_maps(exe):
    env = dict(os.environ, LD_DEBUG="files")
    env.pop("GLIBC_TUNABLES", None)
    env.pop("CMS_HUGE_PAGES_EXECUTED", None)
    r = subprocess.run([exe, "--version"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0 or not r.stdout.startswith("cms "):
        sys.exit(f"check_one_start: {exe} --version failed ({r.returncode}): {r.stdout} {r.stderr[-2000:]}")
    return sum(1 for line in r.stderr.splitlines()
               if "libtrilinos_tpetra.so" in line and "generating link map" in line)


def main():
    launcher = os.path.abspath(sys.argv[1])
    engine = os.path.join(os.path.dirname(launcher), "cms-engine")
    through, direct = tpetra_maps(launcher), tpetra_maps(engine)
    print(f"libtrilinos_tpetra mapped: {through} through the launcher, {direct} by the engine alone")
    if through != 1:
        sys.exit(f"check_one_start: the engine started {through} times through the launcher (expected once)")
    with tempfile.TemporaryDirectory() as d:
        lone = os.path.join(d, "cms")
        shutil.copy2(launcher, lone)
        r = subprocess.run([lone, "--version"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode != 5 or "cannot start the engine" not in r.stderr or os.path.join(d, "cms-engine") not in r.stderr:
            sys.exit(f"check_one_start: a launcher without its engine gave {r.returncode}: {r.stdout!r} {r.stderr!r}")
        if r.stdout:
            sys.exit(f"check_one_start: a launcher without its engine wrote {r.stdout!r}")
        # Its own start maps glibc alone (the C++ runtime is linked in).
        env = dict(os.environ, LD_DEBUG="files")
        r = subprocess.run([lone, "--version"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        mapped = sorted({line.split("file=")[1].split()[0] for line in r.stderr.splitlines()
                         if "file=" in line and "generating link map" in line})
        if not mapped or any(not name.startswith(("libc.so", "libm.so")) for name in mapped):
            sys.exit(f"check_one_start: the launcher maps {mapped}, not glibc alone")
        print(f"the launcher maps {', '.join(mapped)}")
    print("check_one_start: ok")


if __name__ == "__main__":
    main()
