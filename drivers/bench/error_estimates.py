#!/usr/bin/env python3
"""Estimated against true error, per mode, on every example scene, the rotor
benchmark at two mesh sizes and the solid blade (issue #9; doc/benchmarks.md,
"Error estimates against the truth"). Runs `cms modes --truth` on each case
(the truth solve only to validate: the estimate itself needs none), reads the
JSON's "error_estimate" and "true_error" per mode, and writes
doc/bench/error-estimates-scenes.csv (one row per mode) and a markdown summary
on stdout.

usage: python3 drivers/bench/error_estimates.py [build/drivers/cms] [out.csv]
"""
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CMS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "drivers", "cms")
OUT = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "doc", "bench", "error-estimates-scenes.csv")
SCENES = os.path.join(ROOT, "drivers", "scenes")
CASES = [(name, [os.path.join(SCENES, name + ".yaml")]) for name in
         ("spacecraft", "rotating-blade", "shaft-on-support", "rotor-chain", "solid-blade")]
ROTOR = os.path.join(ROOT, "drivers", "bench", "rotor", "rotor.yaml")
CASES += [("rotor h=0.03", [ROTOR, "--mesh-parameters=h=0.03"]),
          ("rotor h=0.02", [ROTOR, "--mesh-parameters=h=0.02"])]


def main():
    rows = []
    print("| case | DOFs (truth) | modes | true error range | estimate / true, min - max | s |")
    print("|---|---|---|---|---|---|")
    for name, args in CASES:
        with tempfile.TemporaryDirectory() as out:
            t0 = time.time()
            run = subprocess.run([CMS, "modes"] + args + ["--truth", "--output=" + out],
                                 capture_output=True, text=True)
            seconds = time.time() - t0
            if run.returncode != 0:
                print(f"| {name} | failed (exit {run.returncode}): {run.stderr.strip()[:200]} |")
                continue
            js = [f for f in os.listdir(out) if f.endswith(".json")][0]
            result = json.load(open(os.path.join(out, js)))
        dofs = sum(s["physical_dofs"] for s in result["substructures"])
        ratios, errors = [], []
        for k, m in enumerate(result["modes"]):
            est, true = m.get("error_estimate"), m.get("true_error")
            rows.append({"case": name, "mode": k + 1, "hz": m["hz"], "stability": m["stability"] +
                         (" (frame rate)" if m.get("frame_artefact") else ""), "estimated_rel_error": est,
                         "true_rel_error": true})
            if est is None or true is None or true <= 1e-8:
                continue  # zero frequencies; errors at the truth solve's own rounding
            if m.get("frame_artefact") or m.get("stability") == "neutral":
                # A free body's rigid motions seen at the frame rate: a
                # defective cluster that rounding splits by ~sqrt(eps) s in
                # both solves (theory 4), not a reduction error.
                continue
            errors.append(true)
            ratios.append(est / true)
        rng = f"{min(errors):.1e} - {max(errors):.1e}" if errors else "all below 1e-8"
        rat = f"{min(ratios):.2f} - {max(ratios):.2f}" if ratios else "-"
        print(f"| {name} | {dofs} | {len(result['modes'])} | {rng} | {rat} | {seconds:.0f} |")
    with open(OUT, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["case", "mode", "hz", "stability", "estimated_rel_error", "true_rel_error"])
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
