#!/usr/bin/env python3
"""Checks a cms Campbell table for the physics of gyroscopic whirl:
python3 check_campbell.py <name>-campbell.csv

No track labelled FW (forward whirl) at the top speed may fall with speed,
and no BW track rise (the polar inertia stiffens forward and softens
backward whirl; a whirling mode in which the disc does not tilt stays
flat); at least one FW track must rise and one BW track fall, by more than
1e-6 relative. Exit 0 on success, 1 otherwise.
"""
import csv
import sys

rows = list(csv.DictReader(open(sys.argv[1], newline="")))
tracks = sorted({k[:-3] for k in rows[0] if k.endswith("_hz")})
seen = {"FW": 0, "BW": 0}
bad = []
for t in tracks:
    whirl = rows[-1][t + "_whirl"]
    f0, f1 = float(rows[0][t + "_hz"]), float(rows[-1][t + "_hz"])
    if whirl in seen:
        if (whirl == "FW" and f1 < f0 * (1 - 1e-6)) or (whirl == "BW" and f1 > f0 * (1 + 1e-6)):
            bad.append(f"{t}: {whirl} but {f0} -> {f1} Hz")
        if (whirl == "FW" and f1 > f0 * (1 + 1e-6)) or (whirl == "BW" and f1 < f0 * (1 - 1e-6)):
            seen[whirl] += 1
if bad or not seen["FW"] or not seen["BW"]:
    print("check_campbell:", "; ".join(bad) or f"no FW or BW track ({seen})")
    sys.exit(1)
print(f"check_campbell: {seen['FW']} forward tracks rise, {seen['BW']} backward tracks fall, none the wrong way")
