#!/usr/bin/python3
"""The launcher finds cms-engine beside itself even without /proc, and never
in the working directory.

usage: check_launcher_without_proc.py LAUNCHER

The launcher locates its own directory by /proc/self/exe. Where that link
cannot be read (no /proc mounted: a container, a chroot), it used to
execute "cms-engine" as a relative name, that is a file of that name in
the working directory. Now it takes the directory of the path it was
started by, and refuses (exit 5, a message) when started by a bare name
found on the PATH. Run in a private mount namespace with an empty /proc
(unshare, which needs root: the test is skipped, exit 77, where it cannot
make one), on a copy of the launcher beside a stand-in engine, in a
directory holding a decoy engine.
"""
import os
import shutil
import subprocess
import sys
import tempfile

SKIP = 77


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    launcher = os.path.abspath(sys.argv[1])
    unshare = shutil.which("unshare")
    if os.geteuid() != 0 or unshare is None:
        print("skipped: needs root and unshare for a mount namespace without /proc")
        return SKIP
    with tempfile.TemporaryDirectory() as d:
        bindir, work = os.path.join(d, "bin"), os.path.join(d, "work")
        os.makedirs(bindir)
        os.makedirs(work)
        shutil.copy2(launcher, os.path.join(bindir, "cms"))
        for where, said in ((bindir, "engine beside the launcher"), (work, "decoy in the working directory")):
            path = os.path.join(where, "cms-engine")
            with open(path, "w") as f:
                f.write(f"#!/bin/sh\necho '{said}'\n")
            os.chmod(path, 0o755)

        def without_proc(command):
            script = f"mount -t tmpfs none /proc && cd {work} && {command}"
            return subprocess.run([unshare, "--mount", "--propagation", "private", "sh", "-c", script],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

        probe = without_proc("test ! -e /proc/self/exe")
        if probe.returncode != 0:
            print(f"skipped: no mount namespace without /proc here ({probe.stderr.strip()})")
            return SKIP
        # Started by its path: the engine beside it.
        r = without_proc(f"{os.path.join(bindir, 'cms')} --version")
        print(f"by its path: exit {r.returncode}, {r.stdout.strip()!r} {r.stderr.strip()!r}")
        if r.returncode != 0 or r.stdout.strip() != "engine beside the launcher":
            sys.exit("check_launcher_without_proc: started by its path without /proc, the launcher did not "
                     "start the engine beside it")
        # Started by a bare name from the PATH: no directory to go by, refused.
        r = without_proc(f"PATH={bindir}:/usr/bin:/bin cms --version")
        print(f"by a bare name: exit {r.returncode}, {r.stdout.strip()!r} {r.stderr.strip()!r}")
        if r.returncode != 5 or r.stdout or "cms-engine" not in r.stderr or "/proc/self/exe" not in r.stderr:
            sys.exit("check_launcher_without_proc: started by a bare name without /proc, the launcher did not "
                     "refuse with exit code 5 and a message")
    print("check_launcher_without_proc: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
