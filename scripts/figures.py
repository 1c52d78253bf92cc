#!/usr/bin/env python3
"""Draws the figures of a study from the files `master study` wrote.

Usage: figures.py STUDY_DIR   (reads STUDY_DIR/summary.csv and the per-run
CSVs, writes STUDY_DIR/figures/*.png)
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STATUS_COLOURS = {"ok": "#4caf50", "amplified": "#ff9800", "diverged": "#e53935", "failed": "#9e9e9e"}


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_xy(path, xcol, ycol):
    rows = read_rows(path)
    return [float(r[xcol]) for r in rows], [float(r[ycol]) for r in rows]


def num(text):
    return float(text) if text not in ("", "null") else math.nan


def style(method):
    """Colour by scheme, line by coupling type; the resolved variant dotted;
    implicit coupling green, extrapolated inputs brown."""
    colour = "#1f77b4" if "jacobi" in method else "#d62728"
    if method.startswith("wr-xt") or method.startswith("rs-xt"):
        colour = "#ff7f0e" if "jacobi" in method else "#9467bd"
    if "+implicit" in method:
        colour = "#2ca02c"
    elif "+explicit-extrapolate" in method:
        colour = "#8c564b"
    dash = ":" if "resolved" in method else ("-" if "-xx-" in method else "--")
    return colour, dash


def main(study):
    runs = read_rows(os.path.join(study, "summary.csv"))
    out = os.path.join(study, "figures")
    os.makedirs(out, exist_ok=True)
    cases = {r["method"]: r for r in runs if r["group"] == "case"}
    mono = cases["monolithic"]
    x_m, w_m = read_xy(os.path.join(study, mono["folder"], "deflection.csv"), "x_m", "w_m")

    def deflection(run):
        return read_xy(os.path.join(study, run["folder"], "deflection.csv"), "x_m", "w_m")

    usable = {k: r for k, r in cases.items() if k != "monolithic" and r["status"] in ("ok", "amplified")}

    # The paper's Figure 5: deflection at t_end per cut.
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.5), sharey=True)
    for ax, split, title in zip(axes, ("wr", "rs"), ("wheel/rail cut", "rail/sleepers cut")):
        ax.plot(x_m, [w * 1e3 for w in w_m], "k-", lw=3, alpha=0.35, label="monolithic")
        for k, r in sorted(usable.items()):
            if k.startswith(split):
                x, w = deflection(r)
                c, d = style(k)
                ax.plot(x, [v * 1e3 for v in w], color=c, ls=d, lw=1.2, label=k)
        ax.set_title(f"Rail deflection at t_end, {title}")
        ax.set_xlabel("x (m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("w (mm, down)")
    axes[0].invert_yaxis()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "deflection.png"), dpi=110)
    plt.close(fig)

    # The paper's Figure 6: error curves per cut x schedule.
    fig, axes = plt.subplots(2, 2, figsize=(13, 7), sharex=True)
    for i, split in enumerate(("wr", "rs")):
        for j, scheme in enumerate(("jacobi", "gauss-seidel")):
            ax = axes[i][j]
            for k, r in sorted(usable.items()):
                if k.startswith(split) and scheme in k and (scheme != "jacobi" or "gauss" not in k):
                    x, w = deflection(r)
                    c, d = style(k)
                    ax.plot(x, [(a - b) * 1e3 for a, b in zip(w, w_m)], color=c, ls=d, label=k)
            ax.axhline(0, color="k", lw=0.5)
            ax.set_title(f"{'wheel/rail' if split == 'wr' else 'rail/sleepers'}, {scheme}")
            ax.set_ylabel("w - w_monolithic (mm)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
    for ax in axes[1]:
        ax.set_xlabel("x (m)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors.png"), dpi=110)
    plt.close(fig)

    # Speed against accuracy. The legend goes beside the axes: with dozens of
    # methods (a scene with a soil) it would hide the curves, the monolithic
    # reference among them.
    methods = sorted({r["method"] for r in runs if r["method"] != "monolithic"})
    legend_cols = 1 if len(methods) <= 30 else 2
    fig, ax = plt.subplots(figsize=(9 + 2.6 * legend_cols, 6))
    tol = sorted(
        (num(r["wall_s"]), num(r["rel_l2_error_converged"]), r["tolerance_m"])
        for r in runs
        if r["method"] == "monolithic" and r["status"] == "ok" and num(r["rel_l2_error_converged"]) > 0
    )
    if tol:
        ax.plot([t[0] for t in tol], [t[1] for t in tol], "k-o", lw=2, label="monolithic (tolerance sweep)")
        for t in tol:
            ax.annotate(f"tol {float(t[2]):g}", (t[0], t[1]), fontsize=6, xytext=(3, 3), textcoords="offset points")
    for m in methods:
        pts = sorted(
            (num(r["macro_step_s"]), num(r["wall_s"]), num(r["rel_l2_error_converged"]), r["status"])
            for r in runs
            if r["method"] == m and r["status"] in ("ok", "amplified") and num(r["rel_l2_error_converged"]) > 0
        )
        if not pts:
            continue
        c, d = style(m)
        ax.plot([p[1] for p in pts], [p[2] for p in pts], color=c, ls=d, marker=".", label=m)
        amp = [p for p in pts if p[3] == "amplified"]
        ax.plot([p[1] for p in amp], [p[2] for p in amp], "x", color=c, ms=8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("relative L2 error of the deflection at t_end (vs converged)")
    ax.set_title("Speed against accuracy (x: amplified; each point a macro step)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, ncol=legend_cols, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "speed_accuracy.png"), dpi=110)
    plt.close(fig)

    # Stability map.
    steps = sorted({num(r["macro_step_s"]) for r in runs if r["method"] != "monolithic"})
    status = {(r["method"], num(r["macro_step_s"])): r["status"] for r in runs if r["method"] != "monolithic"}
    fig, ax = plt.subplots(figsize=(1.2 * len(steps) + 3, 0.45 * len(methods) + 1.5))
    for i, m in enumerate(methods):
        for j, h in enumerate(steps):
            s = status.get((m, h), "")
            ax.add_patch(plt.Rectangle((j, i), 1, 1, color=STATUS_COLOURS.get(s, "white"), ec="white"))
            ax.text(j + 0.5, i + 0.5, s, ha="center", va="center", fontsize=7)
    ax.set_xlim(0, len(steps))
    ax.set_ylim(0, len(methods))
    ax.set_xticks([j + 0.5 for j in range(len(steps))], [f"{h:g}" for h in steps])
    ax.set_yticks([i + 0.5 for i in range(len(methods))], methods)
    ax.set_xlabel("macro step H (s)")
    ax.set_title("Stability map")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "stability_map.png"), dpi=110)
    plt.close(fig)

    # Contact force: monolithic, best and worst co-simulation at the scene's H.
    fig, ax = plt.subplots(figsize=(11, 4.5))
    t, f = read_xy(os.path.join(study, mono["folder"], "history.csv"), "t_s", "contact_force_N")
    ax.plot(t, [v / 1e3 for v in f], "k-", lw=2.5, alpha=0.4, label="monolithic")
    if usable:
        ranked = sorted(usable.values(), key=lambda r: num(r["rel_l2_error"]))
        for r, label in ((ranked[0], "best"), (ranked[-1], "worst")):
            t, f = read_xy(os.path.join(study, r["folder"], "history.csv"), "t_s", "contact_force_N")
            ax.plot(t, [v / 1e3 for v in f], lw=1, label=f"{label}: {r['method']}")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("contact force (kN)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "contact_force.png"), dpi=110)
    plt.close(fig)

    spectra(os.path.join(study, mono["folder"], "spectra.csv"), out)


def spectra(path, out):
    """One-third-octave band levels of the monolithic run: contact forces and
    the energy mean of the ballast forces over the sleepers (if written)."""
    if not os.path.exists(path):
        return
    bands = {}
    for r in read_rows(path):
        centre, rms = num(r["centre_Hz"]), num(r["rms"])
        name = r["signal"]
        if name.startswith("ballast_force_"):
            name = "ballast force (mean over sleepers)"
        bands.setdefault(name, {}).setdefault(centre, []).append(rms)
    fig, ax = plt.subplots(figsize=(11, 4.5))
    for name, per_band in sorted(bands.items()):
        xs = sorted(per_band)
        ys = [math.sqrt(sum(v * v for v in per_band[x]) / len(per_band[x])) for x in xs]
        pts = [(x, 20 * math.log10(y)) for x, y in zip(xs, ys) if y > 0]
        if pts:
            ax.semilogx([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, lw=1.2, label=name)
    ax.set_xlabel("one-third-octave band centre (Hz)")
    ax.set_ylabel("band level (dB re 1 N)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    ax.set_title("Force spectra of the monolithic run")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "spectra.png"), dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
