#!/usr/bin/env python3
"""Plots of the cms driver's CSV tables (doc/user-guide.md, "Plots").

    python3 plot_results.py campbell  <name>-campbell.csv  out.png
    python3 plot_results.py compare   <name>-compare.csv   out.png   (error vs DOFs and the Pareto plot)
    python3 plot_results.py truncate  <name>-truncate.csv  out.png
    python3 plot_results.py rotor     bench_rotor.csv      out.png   (bench_rotor: error vs time per size)

Uses Debian's python3-matplotlib with the non-interactive Agg backend; the
format follows the output's extension (png, svg, pdf). Exit code 2 for a
malformed table.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no rows")
    return rows


def num(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def campbell(rows, out):
    speed_key = [k for k in rows[0] if k.endswith("_rad_per_s")][0]
    speeds = [num(r[speed_key]) for r in rows]
    tracks = sorted({k[: -len("_hz")] for k in rows[0] if k.endswith("_hz")}, key=lambda t: int(t[5:]))
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for t in tracks:
        hz = [num(r[t + "_hz"]) for r in rows]
        whirl = [r.get(t + "_whirl", "") for r in rows]
        backward = sum(w == "BW" for w in whirl) > sum(w == "FW" for w in whirl)
        ax.plot(speeds, hz, "--" if backward else "-", lw=1.2)
        bad = [(s, h) for s, h, r in zip(speeds, hz, rows) if r[t + "_stability"] not in ("stable", "rigid", "neutral")]
        if bad:
            ax.plot([b[0] for b in bad], [b[1] for b in bad], "rx", ms=6)
    # Shade the speed ranges where any track is unstable.
    unstable = [any(r[t + "_stability"] not in ("stable", "rigid", "neutral", "lost") for t in tracks) for r in rows]
    for i, u in enumerate(unstable):
        if u:
            lo = speeds[i - 1] if i > 0 and not unstable[i - 1] else speeds[i]
            hi = speeds[i + 1] if i + 1 < len(speeds) else speeds[i]
            ax.axvspan(lo, hi, color="red", alpha=0.12, lw=0)
    top = max(speeds)
    for order in (1, 2):
        ax.plot([0, top], [0, order * top / (2 * math.pi)], "k--", lw=0.8)
        ax.annotate(f"{order}X", (top, order * top / (2 * math.pi)), fontsize=8)
    ymax = max(num(r[t + "_hz"]) for r in rows for t in tracks if not math.isnan(num(r[t + "_hz"])))
    ax.set_ylim(0, 1.05 * ymax)
    ax.set_xlabel(f"{speed_key[:-len('_rad_per_s')]} speed (rad/s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title("Campbell diagram (tracked by MAC; solid: forward or no whirl, dashed: backward; shaded/x: unstable)",
                 fontsize=9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def compare(rows, out):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for strategy in dict.fromkeys(r["strategy"] for r in rows):
        sel = [r for r in rows if r["strategy"] == strategy]
        dofs = [num(r["reduced_dofs"]) for r in sel]
        err = [max(num(r["max_rel_error"]), 1e-16) for r in sel]
        secs = [num(r["reduce_s"]) + num(r["solve_s"]) for r in sel]
        a1.semilogy(dofs, err, "o-", label=strategy)
        a2.loglog(secs, err, "o", label=strategy)
    a1.set_xlabel("reduced DOFs")
    a1.set_ylabel("max relative frequency error")
    a1.set_title("convergence")
    a2.set_xlabel("reduction + solve time (s)")
    a2.set_title(f"speed / accuracy (truth: {num(rows[0]['truth_s']):.3g} s)")
    for a in (a1, a2):
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def truncate(rows, out):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.semilogy([num(r["dofs"]) for r in rows], [max(num(r["max_rel_error"]), 1e-16) for r in rows], "o-")
    for r in rows[1:]:
        ax.annotate(r["changed"], (num(r["dofs"]), max(num(r["max_rel_error"]), 1e-16)), fontsize=7)
    ax.set_xlabel("reduced DOFs")
    ax.set_ylabel("max estimated relative frequency error")
    ax.set_title("truncation study (label: substructure given more vectors)")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def rotor(rows, out):
    """bench_rotor's Pareto plot: max error over the lowest modes against
    pipeline time as a fraction of the truth's, one panel per mesh size, with
    the floor (one CHOLMOD factorisation) as a vertical line."""
    sizes = list(dict.fromkeys(r["h"] for r in rows))
    fig, axes = plt.subplots(1, len(sizes), figsize=(4.2 * len(sizes), 4.2), squeeze=False)
    for ax, h in zip(axes[0], sizes):
        sel = [r for r in rows if r["h"] == h]
        truth = [r for r in sel if r["what"] == "truth"]
        floor = [r for r in sel if r["what"] == "floor"]
        truth_s = num(truth[0]["truth_s"]) if truth else math.nan
        for strategy in dict.fromkeys(r["strategy"] for r in sel if r["what"] == "reduced"):
            pts = [r for r in sel if r["what"] == "reduced" and r["strategy"] == strategy
                   and num(r["max_rel_error"]) >= 0 and num(r["pipeline_s"]) > 0]
            if not pts:
                continue
            ax.loglog([num(r["pipeline_s"]) for r in pts], [max(num(r["max_rel_error"]), 1e-16) for r in pts],
                      "o-", label=strategy)
            for r in pts:
                ax.annotate(r["vectors"], (num(r["pipeline_s"]), max(num(r["max_rel_error"]), 1e-16)), fontsize=7)
        if floor:
            ax.axvline(num(floor[0]["floor_s"]), color="k", ls=":", label="1 CHOLMOD of K")
        if truth:
            ax.axvline(truth_s, color="r", ls="--", label="truth solve")
            ax.axvline(truth_s / 20, color="r", ls=":", label="truth / 20")
        ax.axhline(1e-3, color="g", ls=":", label="0.1%")
        ax.set_xlabel("reduce + synthesise + solve (s)")
        ax.set_title(f"h = {h} m, {int(num(sel[0]['physical_dofs']))} DOFs", fontsize=9)
        ax.grid(alpha=0.3, which="both")
    axes[0][0].set_ylabel("max relative error, lowest modes")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main(argv):
    if len(argv) != 4 or argv[1] not in ("campbell", "compare", "truncate", "rotor"):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        rows = read(argv[2])
        {"campbell": campbell, "compare": compare, "truncate": truncate, "rotor": rotor}[argv[1]](rows, argv[3])
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"plot_results: {argv[2]}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
