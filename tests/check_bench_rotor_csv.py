#!/usr/bin/env python3
"""bench_rotor's CSV as drivers/plot_results.py (rotor) and doc/benchmarks.md
read it: exactly these columns, in this order; for each size an assembly,
truth and floor row; every reduced row either measured (pipeline > 0, an
error against the truth, bases + synthesis + solve = pipeline) or noted as
skipped or failed; a sweep row when --steps > 0. With --turned-copies the
assembly row notes that the copies' matrices were turned from their
prototype's (theory 15.2); with --adopted the first reduced row of each size
names the substructures whose basis adopted the prestress factorisation
(theory 11.4); with --estimates every measured reduced row notes how long
its error estimates took (a positive time) and the largest (a finite
estimate >= 0; theory 11.8).

    check_bench_rotor_csv.py CSV [--turned-copies] [--adopted] [--estimates]
"""
import csv
import math
import re
import sys

COLUMNS = ("h,physical_dofs,truth_dofs,ranks,what,strategy,vectors,reduced_dofs,assembly_s,reduce_s,synthesis_s,"
           "solve_s,pipeline_s,truth_s,floor_s,pipeline_over_truth,pipeline_over_floor,peak_mib_max_rank,"
           "peak_mib_sum,resident_at_start_mib,full_k_m_factor_mib,max_rel_error,mean_rel_error,worst_mac,note,"
           "frequencies_hz").split(",")


def main():
    flags = set(sys.argv[2:])
    with open(sys.argv[1], newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [dict(zip(header, r)) for r in reader]
    problems = []
    if header != COLUMNS:
        problems.append(f"columns {header} are not {COLUMNS}")
    for h in dict.fromkeys(r["h"] for r in rows):
        sel = [r for r in rows if r["h"] == h]
        for what in ("assembly", "floor", "truth"):
            if not any(r["what"] == what for r in sel):
                problems.append(f"h = {h}: no {what} row")
        reduced = [r for r in sel if r["what"] == "reduced"]
        if not reduced:
            problems.append(f"h = {h}: no reduced row")
        assembly = [r for r in sel if r["what"] == "assembly"]
        if "--turned-copies" in flags and not any("turned (no assembly" in r["note"] for r in assembly):
            problems.append(f"h = {h}: the assembly row does not note the copies turned: {[r['note'] for r in assembly]}")
        if "--adopted" in flags and reduced and "prestress factorisation adopted by" not in reduced[0]["note"]:
            problems.append(f"h = {h}: the first reduced row adopted no prestress factorisation: {reduced[0]['note']}")
        for r in reduced:
            tag = f"h = {h}, {r['strategy']} {r['vectors']}"
            if r["note"].startswith(("skipped", "FAILED")):
                continue
            if "--estimates" in flags:
                m = re.search(r"error estimates (\S+) s after the pipeline \(largest (\S+)\)", r["note"])
                if not m:
                    problems.append(f"{tag}: no error estimates in the note: {r['note']}")
                elif not (float(m.group(1)) > 0 and math.isfinite(float(m.group(2))) and float(m.group(2)) >= 0):
                    problems.append(f"{tag}: error estimates {m.group(1)} s, largest {m.group(2)}")
            pipeline = float(r["pipeline_s"])
            parts = float(r["reduce_s"]) + float(r["synthesis_s"]) + float(r["solve_s"])
            # The parts are the pipeline's wall times, printed with 6 digits.
            if not pipeline > 0 or abs(parts - pipeline) > 1e-5 * pipeline:
                problems.append(f"{tag}: bases + synthesis + solve = {parts}, pipeline {pipeline}")
            if not float(r["truth_s"]) > 0 or not float(r["pipeline_over_truth"]) > 0:
                problems.append(f"{tag}: no truth time or ratio (truth_s {r['truth_s']})")
            err = float(r["max_rel_error"])
            if not (math.isfinite(err) and err >= 0):
                problems.append(f"{tag}: max_rel_error {err} (no comparison with the truth)")
            if len(r["frequencies_hz"].split(";")) < 1 or not r["frequencies_hz"]:
                problems.append(f"{tag}: no frequencies")
        if not any(r["what"] == "sweep" for r in sel):
            problems.append(f"h = {h}: no sweep row")
    for p in problems:
        print("FAILED:", p)
    print("PASSED" if not problems else f"FAILED: {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
