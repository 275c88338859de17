#!/usr/bin/env python3
"""Plots of the cms driver's CSV tables (doc/user-guide.md, "Plots").

    python3 plot_results.py campbell  <name>-campbell.csv  out.png  [--orders=1,2] [--axis=hz|rpm|per-rev]
                                        (crossings from <name>-campbell-crossings.csv when present;
                                         orders default to those crossed, else 1X)
    python3 plot_results.py compare   <name>-compare.csv   out.png   (error vs DOFs and the Pareto plot)
    python3 plot_results.py truncate  <name>-truncate.csv  out.png
    python3 plot_results.py rotor     bench_rotor.csv      out.png   (bench_rotor: error vs time per size)

Uses Debian's python3-matplotlib with the non-interactive Agg backend; the
format follows the output's extension (png, svg, pdf). Exit code 2 for a
malformed table.
"""
import csv
import math
import os
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


def campbell(rows, out, orders=None, axis="rpm", crossings=None):
    """The Campbell diagram an engineer reads: the reference speed (the
    first *_rad_per_s column; the x-axis also names every other rate scaled
    with it and those held) in rev/s (axis hz), rpm (rpm) or rpm with
    frequencies per revolution (per-rev: engine orders are horizontal);
    forward-whirl tracks solid, backward dash-dot, neither dotted, each in
    its own colour; engine-order lines dashed grey; frame-rate tracks (rigid
    motions seen at a spin rate) faint; crossings marked (filled: forward,
    which unbalance excites at 1X; open: backward); a legend. Beside it,
    when the table has track<i>_damping_ratio columns (doc/theory.md §13),
    the damping ratio of each track against the same speed axis, in the
    same style; below zero (shaded) a mode grows."""
    from matplotlib.lines import Line2D

    rate_keys = [k for k in rows[0] if k.endswith("_rad_per_s")]
    ref_key = rate_keys[0]
    ref = ref_key[: -len("_rad_per_s")]
    omega = [num(r[ref_key]) for r in rows]
    rpm = [w * 60 / (2 * math.pi) for w in omega]
    xs = [w / (2 * math.pi) for w in omega] if axis == "hz" else rpm
    xunit = "rev/s" if axis == "hz" else "rpm"
    per_rev = axis == "per-rev"

    def y_of(hz, w):
        if not per_rev:
            return hz
        return hz * 2 * math.pi / abs(w) if w else math.nan

    tracks = sorted({k[: -len("_hz")] for k in rows[0] if k.endswith("_hz")}, key=lambda t: int(t[5:]))
    # The damping panel only for a damped structure: an undamped one has
    # zeta = 0 to rounding on every track.
    damped = any(abs(num(r[k])) > 1e-9 for r in rows for k in rows[0]
                 if k.endswith("_damping_ratio") and not math.isnan(num(r[k])))
    if damped:
        fig, (ax, axz) = plt.subplots(1, 2, figsize=(15, 6), gridspec_kw={"width_ratios": [3, 2]})
    else:
        fig, ax = plt.subplots(figsize=(9, 6))
        axz = None
    # Track colours: the default cycle without its grey (grey is for engine orders).
    colours = [c for c in plt.rcParams["axes.prop_cycle"].by_key()["color"] if c.lower() != "#7f7f7f"]
    ymax = 0.0
    for i, t in enumerate(tracks):
        hz = [num(r[t + "_hz"]) for r in rows]
        ys = [y_of(h, w) for h, w in zip(hz, omega)]
        ymax = max([ymax] + [y for y in ys if not math.isnan(y)])
        whirl = [r.get(t + "_whirl", "") for r in rows]
        fw, bw = sum(w == "FW" for w in whirl), sum(w == "BW" for w in whirl)
        if rows[0].get(t + "_frame_rate") == "yes":
            ax.plot(xs, ys, ":", color="0.75", lw=1.0)
            continue
        style = "-" if fw > bw else "-." if bw > fw else ":"
        ax.plot(xs, ys, style, color=colours[i % len(colours)], lw=1.4)
        if axz is not None:
            zeta = [num(r.get(t + "_damping_ratio")) for r in rows]
            axz.plot(xs, zeta, style, color=colours[i % len(colours)], lw=1.4, label=t)
        bad = [(x, y) for x, y, r in zip(xs, ys, rows) if r[t + "_stability"] not in ("stable", "rigid", "neutral")]
        if bad:
            ax.plot([b[0] for b in bad], [b[1] for b in bad], "rx", ms=6)
    # Shade the speed ranges where any track is unstable.
    unstable = [any(r[t + "_stability"] not in ("stable", "rigid", "neutral", "lost") for t in tracks) for r in rows]
    for i, u in enumerate(unstable):
        if u:
            lo = xs[i - 1] if i > 0 and not unstable[i - 1] else xs[i]
            hi = xs[i + 1] if i + 1 < len(xs) else xs[i]
            ax.axvspan(lo, hi, color="red", alpha=0.12, lw=0)
    top = max(xs)
    if not orders:
        orders = sorted({num(c["order"]) for c in crossings or []}) or [1.0]
    ylim = 1.1 * max([ymax] + ([max(orders)] if per_rev else []))
    for order in orders:
        label = f"{order:g}X"
        if per_rev:
            ax.axhline(order, color="0.5", ls="--", lw=0.9)
            ax.annotate(label, (top, order), fontsize=8, color="0.35", ha="right", va="bottom")
        else:
            # omega = order * Omega: in Hz, order * (rev/s); against rpm, order * rpm / 60.
            slope = order if axis == "hz" else order / 60.0
            ax.plot([0, top], [0, slope * top], "--", color="0.5", lw=0.9)
            xe = min(top, ylim / slope) if slope > 0 else top
            ax.annotate(label, (xe, slope * xe), fontsize=8, color="0.35", ha="right", va="bottom")
    for c in crossings or []:
        w = num(c["speed_rad_per_s"])
        x = w / (2 * math.pi) if axis == "hz" else w * 60 / (2 * math.pi)
        y = num(c["order"]) if per_rev else num(c["frequency_hz"])
        forward = c["whirl"] == "FW"
        ax.plot([x], [y], "o", ms=7, mfc="k" if forward else "none", mec="k")
    ax.set_xlim(0, top)
    ax.set_ylim(0, ylim)
    # The x-axis names every rate: the reference, those scaled with it (as
    # multiples of it) and those held.
    scaled, held = [], []
    last = rows[-1]
    for k in rate_keys[1:]:
        name = k[: -len("_rad_per_s")]
        values = [num(r[k]) for r in rows]
        if max(values) != min(values):
            ratio = num(last[k]) / num(last[ref_key]) if num(last[ref_key]) else math.nan
            scaled.append(f"{name} = {ratio:.4g} x {ref}")
        else:
            held.append(f"{name} = {values[0]:.4g} rad/s")
    xlabel = f"{ref} speed ({xunit})"
    if scaled:
        xlabel += "; scaled with it: " + ", ".join(scaled)
    if held:
        xlabel += "; held: " + ", ".join(held)
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_ylabel(f"frequency / {ref} speed (per rev)" if per_rev else "frequency (Hz)")
    ax.set_title("Campbell diagram (modes tracked by MAC)", fontsize=10)
    handles = [
        Line2D([], [], color="k", ls="-", label="forward whirl (a colour per track)"),
        Line2D([], [], color="k", ls="-.", label="backward whirl"),
        Line2D([], [], color="k", ls=":", label="no whirl / unresolved"),
        Line2D([], [], color="0.5", ls="--", label="engine orders (" + ", ".join(f"{o:g}X" for o in orders) + ")"),
        Line2D([], [], color="0.75", ls=":", label="frame-rate rigid motion (not a vibration)"),
        Line2D([], [], ls="", marker="o", mfc="k", mec="k", label="critical speed, forward (unbalance excites 1X)"),
        Line2D([], [], ls="", marker="o", mfc="none", mec="k", label="critical speed, backward"),
        Line2D([], [], ls="", marker="x", color="r", label="unstable"),
    ]
    ax.legend(handles=handles, fontsize=7, loc="best", framealpha=0.9)
    ax.grid(alpha=0.3)
    if axz is not None:
        axz.axhline(0.0, color="r", lw=0.9)
        axz.set_xlim(0, top)
        lo, hi = axz.get_ylim()
        if lo < 0:
            axz.axhspan(lo, 0.0, color="red", alpha=0.08, lw=0)
        axz.set_ylim(lo, hi)
        axz.set_xlabel(f"{ref} speed ({xunit})", fontsize=9)
        axz.set_ylabel("damping ratio zeta = -Re(lambda) / |lambda|")
        axz.set_title("damping ratio (below 0: unstable)", fontsize=10)
        axz.grid(alpha=0.3)
        axz.legend(fontsize=7, loc="best", framealpha=0.9)
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
    options = {a.split("=", 1)[0]: a.split("=", 1)[1] for a in argv[1:] if a.startswith("--") and "=" in a}
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 4 or args[1] not in ("campbell", "compare", "truncate", "rotor") or \
            set(options) - {"--orders", "--axis"} or options.get("--axis", "rpm") not in ("hz", "rpm", "per-rev"):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        rows = read(args[2])
        if args[1] == "campbell":
            orders = [float(o) for o in options["--orders"].split(",")] if "--orders" in options else None
            side = args[2][: -len(".csv")] + "-crossings.csv" if args[2].endswith(".csv") else None
            crossings = None
            if side and os.path.exists(side):
                with open(side, newline="") as f:
                    crossings = list(csv.DictReader(f))
            campbell(rows, args[3], orders, options.get("--axis", "rpm"), crossings)
        else:
            {"compare": compare, "truncate": truncate, "rotor": rotor}[args[1]](rows, args[3])
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"plot_results: {args[2]}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
