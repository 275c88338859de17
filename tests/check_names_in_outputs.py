#!/usr/bin/python3
"""Names and text the outputs must carry intact.

usage: check_names_in_outputs.py CMS MPIEXEC SCENE OUTDIR

SCENE (tests/data/scenes/names-in-outputs.yaml) is named "R&D <rig>",
holds a substructure "blade, stage 1" and a comment in Latin-1. Found by a
review, each failed before:
  - `cms modes` solved, then the JSON writer threw on the comment's byte
    (not UTF-8): exit 5, an internal error; on two ranks a hang;
  - `cms modes --vtu` wrote a .pvd whose file attribute held & and <: not
    XML, ParaView could not open it;
  - `cms campbell` wrote the substructure's name unquoted into the CSV's
    header, so every row had one field fewer than the header.
"""
import csv
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

cms, mpiexec, scene, out = sys.argv[1:5]
FAILED = []


def run(cmd, where):
    os.makedirs(where, exist_ok=True)
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=300)
    except subprocess.TimeoutExpired:
        FAILED.append("%s: no answer in 300 s (a hang)" % " ".join(cmd))
        return False
    if p.returncode != 0:
        FAILED.append("%s: exit %d\n%s%s" % (" ".join(cmd), p.returncode, p.stdout[-2000:], p.stderr[-2000:]))
        return False
    return True


base = "R&D <rig>"
for ranks in (1, 2):
    where = os.path.join(out, "np%d" % ranks)
    cmd = ([mpiexec, "-n", "2"] if ranks == 2 else []) + [cms, "modes", scene, "--vtu", "--output=" + where]
    if not run(cmd, where):
        continue
    with open(os.path.join(where, base + ".json"), encoding="utf-8") as f:
        doc = json.load(f)
    text = doc.get("scene_text", "")
    if "L\ufffdnge" not in text:
        FAILED.append("np%d: the scene's Latin-1 byte is not recorded as U+FFFD in the JSON" % ranks)
    try:
        root = ET.parse(os.path.join(where, base + "-modes.pvd")).getroot()
        files = [d.get("file") for d in root.iter("DataSet")]
        if not files or not all(f.startswith(base + "-mode-") for f in files):
            FAILED.append("np%d: the .pvd names %s" % (ranks, files))
        for f in files:
            if not os.path.exists(os.path.join(where, f)):
                FAILED.append("np%d: the .pvd names %s, which was not written" % (ranks, f))
    except ET.ParseError as e:
        FAILED.append("np%d: the .pvd is not XML: %s" % (ranks, e))

where = os.path.join(out, "campbell")
if run([cms, "campbell", scene, "--steps=3", "--output=" + where], where):
    for name in (base + "-campbell.csv", base + "-campbell-crossings.csv"):
        with open(os.path.join(where, name), newline="") as f:
            rows = list(csv.reader(f))
        bad = [i + 1 for i, r in enumerate(rows) if len(r) != len(rows[0])]
        if bad:
            FAILED.append("%s: rows %s have a field count other than the header's %d" % (name, bad[:5], len(rows[0])))
        if name.endswith("campbell.csv") and "blade, stage 1_rad_per_s" not in rows[0]:
            FAILED.append("%s: no column 'blade, stage 1_rad_per_s' in %s" % (name, rows[0][:4]))

for f in FAILED:
    print("FAILED:", f)
print("names in outputs: %d failure(s)" % len(FAILED))
sys.exit(1 if FAILED else 0)
