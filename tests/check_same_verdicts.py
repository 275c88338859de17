#!/usr/bin/env python3
"""Same stability verdict at every rank count (issue "No silent wrong
numbers" item 6): the Campbell CSVs of one scene run at 1, 2 and 4 ranks
must agree on every track's stability, and on its frequency. What differs
between rank counts is the summation order of the distributed projections:
a simple eigenvalue moves by eps times its condition (1e-9 of the largest
frequency is far above that), but a defective cluster (a free body's rigid
motions seen at the frame rate) splits by sqrt(eta) s, which at these sizes
is 1e-5 of the cluster's frequency (measured 6e-5 at worst): a track within
1e-3 of another track, or neutral, is compared to 3e-4 of its value;
a rigid track's frequency is rounding and only its verdict is compared.
A frame-rate track (a rigid motion seen at a spin rate: frame_rate "yes")
is one member of such a defective cluster, split by sqrt(eta) s whatever
the rate: at the antenna's 0.2 rad/s the members moved by 3.6e-4 of their
value between rank counts on another CPU (the 3e-4 above failed). Its
members are therefore not compared one by one; the cluster's mean (its
trace, determined to eta s like a simple eigenvalue) is, to 1e-9 of the
largest frequency (measured 3.9e-11 of its value).
Whirl labels must agree too: the whirl rule classifies a degenerate cluster
as a whole and calls a mode in which the spinning part barely moves neutral
(analysis::WhirlClassification, theory §12.2), so no label depends on the
basis or the rounding a rank count gives. Where the stability verdicts
already differ (reported above) a whirl difference is only printed.

usage: check_same_verdicts.py reference.csv other.csv [other.csv ...]
"""
import csv
import sys


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def frame_rate_means(row):
    """The means of the frame-rate tracks' clusters (members within 1e-3 of
    each other), ascending."""
    hz = sorted(float(row[k]) for k in row
                if k.endswith("_hz") and row.get(k[: -len("_hz")] + "_frame_rate") == "yes"
                and row[k] not in ("", "nan"))
    clusters = []
    for f in hz:
        if clusters and abs(f - clusters[-1][-1]) <= 1e-3 * abs(f):
            clusters[-1].append(f)
        else:
            clusters.append([f])
    return [sum(c) / len(c) for c in clusters]


def main():
    ref = read(sys.argv[1])
    scale = max(float(v) for row in ref for k, v in row.items() if k.endswith("_hz") and v not in ("", "nan"))
    bad = []
    for path in sys.argv[2:]:
        other = read(path)
        if len(other) != len(ref):
            bad.append(f"{path}: {len(other)} speeds, reference {len(ref)}")
            continue
        for i, (a, b) in enumerate(zip(ref, other)):
            hz = [float(v) for k, v in a.items() if k.endswith("_hz") and v not in ("", "nan")]
            for key in a:
                if key.endswith("_stability"):
                    if a[key] != b[key]:
                        bad.append(f"{path}: speed {i} {key}: {b[key]!r}, 1 rank {a[key]!r}")
                elif key.endswith("_whirl"):
                    stability = key[: -len("_whirl")] + "_stability"
                    if a[key] != b[key]:
                        if a[stability] == b[stability]:
                            bad.append(f"{path}: speed {i} {key}: {b[key]!r}, 1 rank {a[key]!r}")
                        else:
                            print(f"note: {path}: speed {i} {key}: {b[key]!r}, 1 rank {a[key]!r}")
                elif key.endswith("_hz") and a[key] not in ("", "nan"):
                    f = float(a[key])
                    track = key[: -len("_hz")]
                    if a[track + "_stability"] == "rigid":
                        continue  # zero to rounding: its value is rounding (the verdict is compared)
                    if a.get(track + "_frame_rate") == "yes":
                        continue  # a defective cluster's member: its mean is compared below
                    clustered = a[track + "_stability"] == "neutral" or sum(
                        abs(g - f) <= 1e-3 * abs(f) for g in hz) > 1
                    tol = 3e-4 * abs(f) if clustered else 1e-9 * scale
                    if abs(f - float(b[key])) > tol:
                        bad.append(f"{path}: speed {i} {key}: {b[key]}, 1 rank {a[key]} (tolerance {tol:.2g})")
            ma, mb = frame_rate_means(a), frame_rate_means(b)
            if len(ma) != len(mb):
                bad.append(f"{path}: speed {i}: {len(mb)} frame-rate clusters, 1 rank {len(ma)}")
            for x, y in zip(ma, mb):
                if abs(x - y) > 1e-9 * scale:
                    bad.append(f"{path}: speed {i}: a frame-rate cluster's mean {y}, 1 rank {x} "
                               f"(tolerance {1e-9 * scale:.2g})")
    if bad:
        print("\n".join(bad))
        return 1
    print(f"same verdicts and frequencies in {len(sys.argv) - 1} runs, {len(ref)} speeds")
    return 0


if __name__ == "__main__":
    sys.exit(main())
