#!/usr/bin/env python3
"""Checks the columns of a Campbell table and its crossings
(analysis::CampbellResult::writeCsv / writeCrossingsCsv, written by
`cms campbell` and `campbell --csv`):

    check_campbell_csv.py <name>-campbell.csv --reference=NAME [--held=a,b] [--orders=1,2] [--parts=a,b] [--rotor-frame=1] [--min-crossings=N]

- the first columns are factor, then <reference>_rad_per_s, then the other
  rates; a rate named in --held is constant over the sweep, every other one
  is scaled (varies, in proportion to the reference);
- every track has _hz, _stability, _damping_ratio (in [-1, 1] or nan),
  _whirl (FW, BW, -, unresolved) and
  _frame_rate (yes, no) columns;
- <name>-campbell-crossings.csv has the header below, only --orders appear,
  each frequency is order times the speed, rpm is rad/s * 30 / pi, and
  "unbalance" is yes exactly at order 1 for forward whirl, or for a
  backward or unresolved one whose "forward_share" (the orbit's forward
  part, in [0, 1]; empty: not known) is above 1e-2 (never with
  --rotor-frame=1: the whirl part is seen from a spinning frame in which
  its unbalance is no 1X force of the reference), and "dominant"
  names the part (or parts "a & b") of each track (among --parts when
  given: the scene's substructures); rows of order 0 are the zero-frequency
  critical speeds (K(Omega) singular): frequency 0, whirl -, no track or
  dominant part, a speed above 0, and "unbalance" frame (a static load of
  the swept frame excites it).
Exit 0 on success, 1 with the reasons otherwise.
"""
import csv
import math
import sys

CROSSINGS = ["order", "speed_rad_per_s", "speed_rpm", "frequency_hz", "whirl", "unbalance", "tracks", "refined",
             "dominant", "forward_share"]


def main(argv):
    path = argv[1]
    opts = dict(a[2:].split("=", 1) for a in argv[2:])
    ref = opts["reference"]
    held = set(filter(None, opts.get("held", "").split(",")))
    orders = {float(o) for o in opts.get("orders", "1").split(",")}
    parts = set(filter(None, opts.get("parts", "").split(",")))
    rotor_frame = "rotor-frame" in opts
    min_crossings = int(opts.get("min-crossings", "0"))
    bad = []
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [dict(zip(header, r)) for r in reader]
    if header[:2] != ["factor", ref + "_rad_per_s"]:
        bad.append(f"first columns {header[:2]}, expected factor, {ref}_rad_per_s")
    rates = [k for k in header if k.endswith("_rad_per_s")]
    for k in rates[1:]:
        name = k[: -len("_rad_per_s")]
        values = [float(r[k]) for r in rows]
        constant = max(values) == min(values)
        if name in held and (not constant or values[0] == 0.0):
            bad.append(f"{name} should be held at its nominal rate: {values[0]} .. {values[-1]}")
        if name not in held:
            ratios = {round(float(r[k]) / float(r[rates[0]]), 9) for r in rows if float(r[rates[0]]) != 0.0}
            if constant or len(ratios) != 1:
                bad.append(f"{name} should be scaled with {ref}: ratios {sorted(ratios)[:3]}")
    tracks = [k[: -len("_hz")] for k in header if k.endswith("_hz")]
    if not tracks:
        bad.append("no track columns")
    for t in tracks:
        for suffix in ("_stability", "_damping_ratio", "_whirl", "_frame_rate"):
            if t + suffix not in header:
                bad.append(f"{t}{suffix} missing")
        for r in rows:
            if r.get(t + "_whirl") not in ("FW", "BW", "-", "unresolved"):
                bad.append(f"{t}_whirl = {r.get(t + '_whirl')!r}")
                break
            zeta = r.get(t + "_damping_ratio", "")
            if zeta.lower().lstrip("-") != "nan" and not (-1.0 <= float(zeta or "nan") <= 1.0):
                bad.append(f"{t}_damping_ratio = {zeta!r} not in [-1, 1]")
                break
            if r.get(t + "_frame_rate") not in ("yes", "no"):
                bad.append(f"{t}_frame_rate = {r.get(t + '_frame_rate')!r}")
                break
    side = path[: -len(".csv")] + "-crossings.csv"
    with open(side, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        crossings = [dict(zip(header, r)) for r in reader]
    if header != CROSSINGS:
        bad.append(f"{side}: header {header}")
    for c in crossings:
        order, w = float(c["order"]), float(c["speed_rad_per_s"])
        if order == 0.0:
            if (float(c["frequency_hz"]) != 0.0 or c["whirl"] != "-" or c["tracks"] or c["dominant"]
                    or c["unbalance"] != "frame" or c["refined"] not in ("yes", "no") or not w > 0.0):
                bad.append(f"{side}: zero-frequency row {c}")
            if not math.isclose(float(c["speed_rpm"]), w * 30 / math.pi, rel_tol=1e-9):
                bad.append(f"{side}: {c['speed_rpm']} rpm is not {w} rad/s")
            continue
        if order not in orders:
            bad.append(f"{side}: order {order} not asked")
        if not math.isclose(float(c["frequency_hz"]), order * w / (2 * math.pi), rel_tol=1e-9):
            bad.append(f"{side}: {c['frequency_hz']} Hz is not {order} x {w} rad/s")
        if not math.isclose(float(c["speed_rpm"]), w * 30 / math.pi, rel_tol=1e-9):
            bad.append(f"{side}: {c['speed_rpm']} rpm is not {w} rad/s")
        share = float(c["forward_share"]) if c["forward_share"] else -1.0
        if c["forward_share"] and not 0.0 <= share <= 1.0:
            bad.append(f"{side}: forward share {share} outside [0, 1]")
        if c["whirl"] == "FW" and c["forward_share"] and share < 0.5:
            bad.append(f"{side}: forward whirl with a forward share of {share}")
        excited = c["whirl"] == "FW" or (c["whirl"] in ("BW", "unresolved") and share > 1e-2)
        if (c["unbalance"] == "yes") != (order == 1.0 and excited and not rotor_frame):
            bad.append(f"{side}: unbalance {c['unbalance']} for {order}X {c['whirl']} (forward share {share})")
        names = c.get("dominant", "").split(";")
        named = {n for name in names for n in name.split(" & ")}
        if len(names) != len(c["tracks"].split(";")) or not all(names) or (parts and not named <= parts):
            bad.append(f"{side}: dominant {c.get('dominant')!r} for tracks {c['tracks']!r}"
                       + (f" (parts: {sorted(parts)})" if parts else ""))
    fw1 = [c for c in crossings if float(c["order"]) == 1.0 and c["whirl"] == "FW"]
    if len(fw1) < min_crossings:
        bad.append(f"{side}: {len(fw1)} 1X forward crossings, expected at least {min_crossings}")
    if bad:
        print("check_campbell_csv: " + "; ".join(bad))
        return 1
    print(f"check_campbell_csv: {len(tracks)} tracks, {len(rates)} rates, {len(crossings)} crossings: columns right")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
