#!/usr/bin/python3
"""A cms program never loads a shared library from the working directory.

usage: check_working_directory_libraries.py EXECUTABLE...

CMake ends the build tree's RUNPATH with an empty entry (a ':' it pads
with, to rewrite the path in place at install), and the loader reads an
empty entry as the current directory: every program searched the working
directory first for each of its libraries. A file named libmpi.so.40 there
stopped every run ("file too short"), and a real library of that name would
have been loaded in place of Open MPI's. The build now carries no RUNPATH
(CMakeLists.txt, CMAKE_SKIP_BUILD_RPATH; every library is in the system's
directories). Each program is run with --version in a directory holding a
file that is not a library under the name of every library it needs; it
must start, and print its version.
"""
import os
import re
import subprocess
import sys
import tempfile


def needed(exe):
    r = subprocess.run(["ldd", exe], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"check_working_directory_libraries: ldd {exe} failed: {r.stderr}")
    names = [m.group(1) for m in re.finditer(r"^\s*(\S+\.so[.\d]*)\s+=>", r.stdout, re.M)]
    if not names:
        sys.exit(f"check_working_directory_libraries: ldd {exe} lists {len(names)} libraries: {r.stdout}")
    return names


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    failed = []
    for exe in sys.argv[1:]:
        exe = os.path.abspath(exe)
        with tempfile.TemporaryDirectory() as d:
            names = needed(exe)
            for name in names:
                with open(os.path.join(d, name), "w") as f:
                    f.write("not a library\n")
            r = subprocess.run([exe, "--version"], cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            ok = r.returncode == 0 and r.stdout.startswith("cms ")
            print(f"{os.path.basename(exe)}: {len(names)} decoys in the working directory, exit {r.returncode}"
                  + ("" if ok else f": {r.stderr.strip()[-500:]}"))
            if not ok:
                failed.append(exe)
    if failed:
        sys.exit("check_working_directory_libraries: loaded from the working directory: " + ", ".join(failed))


if __name__ == "__main__":
    main()
