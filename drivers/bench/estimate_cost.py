#!/usr/bin/env python3
"""What the accuracy checks of `cms modes` cost (issue 15; doc/benchmarks.md,
"Error estimates against the truth"): per case, the JSON's timings_s of one
run without the truth, median of three runs: assembly, reduction and
synthesis, solve, and the error estimates with their bounds plus the
coverage Sturm counts (one held-stiffness factorisation and one LDL^T per
reduced substructure, SynthesizedStructure::accuracy and ::coverage), and
the latter's share of the four.

usage: python3 drivers/bench/estimate_cost.py [build/drivers/cms]
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CMS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "drivers", "cms")
SCENES = os.path.join(ROOT, "drivers", "scenes")
CASES = [(name, [os.path.join(SCENES, name + ".yaml")]) for name in
         ("spacecraft", "rotating-blade", "shaft-on-support", "rotor-chain", "solid-blade")]
CASES += [("rotor h=0.03", [os.path.join(ROOT, "drivers", "bench", "rotor", "rotor.yaml"),
                            "--mesh-parameters=h=0.03"])]
KEYS = ("assembly", "reduction_and_synthesis", "solve", "error_estimates_and_coverage")  # the pipeline


def main():
    print("| case | DOFs | coordinates | assembly s | reduction s | solve s | estimates + coverage s "
          "(of which estimates) | share |")
    print("|---|---|---|---|---|---|---|---|")
    for name, args in CASES:
        runs = []
        for _ in range(3):
            with tempfile.TemporaryDirectory() as out:
                run = subprocess.run([CMS, "modes"] + args + ["--output=" + out], capture_output=True, text=True)
                if run.returncode != 0:
                    print(f"| {name} | failed (exit {run.returncode}) |")
                    break
                js = [f for f in os.listdir(out) if f.endswith(".json")][0]
                runs.append(json.load(open(os.path.join(out, js))))
        if len(runs) < 3:
            continue
        t = {k: statistics.median(r["timings_s"][k] for r in runs) for k in KEYS}
        dofs = sum(s["physical_dofs"] for s in runs[0]["substructures"])
        coords = sum(s["coordinates"] for s in runs[0]["substructures"])
        share = t["error_estimates_and_coverage"] / sum(t.values())
        est = statistics.median(r["timings_s"]["error_estimates"] for r in runs)
        print(f"| {name} | {dofs} | {coords} | {t['assembly']:.3f} | {t['reduction_and_synthesis']:.3f} | "
              f"{t['solve']:.3f} | {t['error_estimates_and_coverage']:.3f} ({est:.3f}) | {100 * share:.0f}% |")


if __name__ == "__main__":
    main()
