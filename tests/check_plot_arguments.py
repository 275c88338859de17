#!/usr/bin/python3
"""--plot passes the CSV's path to the plot script as an argument, never
through a shell.

usage: check_plot_arguments.py CMS SCENE

The plot command was once a string run by std::system, with the CSV's path
(the scene's Name under the output directory) pasted between single quotes:
a Name holding a quote ran the rest as shell commands (found by a review).
The scene is copied with the Name  x';touch INJECTED;'  and run with
`cms campbell --steps=3 --plot` in an empty directory: the run must
succeed, its CSV must carry the Name as given, and no file INJECTED may
appear.
"""
import os
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    cms, scene = os.path.abspath(sys.argv[1]), sys.argv[2]
    name = "x';touch INJECTED;'"
    with open(scene) as f:
        text = f.read()
    if "  Name: spacecraft\n" not in text:
        sys.exit(f"check_plot_arguments: {scene} has no line '  Name: spacecraft'")
    with tempfile.TemporaryDirectory() as d:
        copy = os.path.join(d, "scene.yaml")
        with open(copy, "w") as f:
            f.write(text.replace("  Name: spacecraft\n", f"  Name: \"{name}\"\n"))
        r = subprocess.run([cms, "campbell", copy, "--steps=3", "--plot", "--output=out"], cwd=d,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        print(r.stdout)
        if r.returncode != 0:
            sys.exit(f"check_plot_arguments: cms exited {r.returncode}")
        if os.path.exists(os.path.join(d, "INJECTED")) or os.path.exists(os.path.join(d, "out", "INJECTED")):
            sys.exit("check_plot_arguments: the scene's Name ran as a shell command")
        csv = os.path.join(d, "out", name + "-campbell.csv")
        if not os.path.isfile(csv):
            sys.exit(f"check_plot_arguments: no {csv}: {sorted(os.listdir(os.path.join(d, 'out')))}")
        if "plotted " not in r.stdout and "no plot: " not in r.stdout:
            sys.exit("check_plot_arguments: --plot said nothing")
    print("check_plot_arguments: the Name stayed an argument")


if __name__ == "__main__":
    main()
