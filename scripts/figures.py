#!/usr/bin/env python3
"""Draws the figures of a study from the files `master study` wrote.

Usage: figures.py [--print-front] STUDY_DIR
  reads STUDY_DIR/summary.csv, STUDY_DIR/front.csv (the report's answer: per
  cut, the cheapest run reaching each accuracy) and the per-run CSVs; writes
  STUDY_DIR/figures/*.png. --print-front also prints the front the
  speed/accuracy chart drew, as CSV (cut,level,method,macro_step_s,
  tolerance_m,wall_s,error), each point read from summary.csv.
The speed/accuracy chart is drawn by speed_accuracy.py beside this file.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from figure_text import title_height, wrapped  # noqa: E402
from speed_accuracy import RAN_TO_END, cut_of, num, read_rows, speed_accuracy  # noqa: E402

STATUS_COLOURS = {"ok": "#4caf50", "inaccurate": "#fff176", "amplified": "#ff9800", "diverged": "#e53935",
                  "not_converged": "#ce93d8", "failed": "#9e9e9e", "not judged": "#e0e0e0"}


def read_xy(path, xcol, ycol):
    rows = read_rows(path)
    return [float(r[xcol]) for r in rows], [float(r[ycol]) for r in rows]


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
    mono = cases.get("monolithic")
    drawn = speed_accuracy(study, runs, out)
    stability_map(runs, out)
    if mono is not None:
        paper_figures(study, cases, lambda r: (mono["folder"], "monolithic"), out)
    else:
        # A participant given by address or a soil of its own: each run over the
        # co-simulation reference of its participants (the study wrote it), not
        # the built-in model, whose physics need not be theirs.
        def reference(r):
            folder = r.get("reference_folder", "")
            if not folder or not os.path.exists(os.path.join(study, folder, "deflection.csv")):
                return None
            return folder, "co-simulation reference (" + folder.split("/")[-1] + ")"

        paper_figures(study, {k: r for k, r in cases.items() if reference(r)}, reference, out)
    return drawn


def paper_figures(study, cases, reference, out):
    """The figures drawn against each run's reference (the monolithic run, or
    the co-simulation reference of its participants): deflection, errors,
    contact force and spectra, one panel per cut (and schedule) that ran."""
    usable = {k: r for k, r in cases.items() if k != "monolithic" and r["status"] in RAN_TO_END}
    if not usable:
        return

    def deflection(folder):
        return read_xy(os.path.join(study, folder, "deflection.csv"), "x_m", "w_m")

    cut_words = {"wr": "wheel/rail", "rs": "rail/sleepers", "ss": "sleepers/soil"}
    order = ("wr", "rs", "ss")
    cuts = sorted({cut_of(k) for k in usable},
                  key=lambda c: [order.index(p) if p in order else len(order) for p in c.split("+")])

    def cut_title(cut):
        return " + ".join(cut_words.get(c, c) for c in cut.split("+")) + " cut"

    # The paper's Figure 5: deflection at t_end per cut, the paper's couplings
    # (explicit, held inputs), over the reference(s) they are judged against.
    ncols = min(3, len(cuts))
    nrows = (len(cuts) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(6.5 * ncols, 4.5 * nrows), sharey=True, squeeze=False)
    for k in range(len(cuts), nrows * ncols):
        axes[k // ncols][k % ncols].axis("off")
    for n, cut in enumerate(cuts):
        ax = axes[n // ncols][n % ncols]
        refs = {reference(r) for k, r in usable.items() if cut_of(k) == cut}
        for folder, label in sorted(refs):
            x_m, w_m = deflection(folder)
            ax.plot(x_m, [w * 1e3 for w in w_m], "k-", lw=3, alpha=0.35, label=label)
        for k, r in sorted(usable.items()):
            if cut_of(k) == cut and not any(tag in k for tag in ("+implicit", "+explicit", "-at-")):
                x, w = deflection(r["folder"])
                c, d = style(k)
                ax.plot(x, [v * 1e3 for v in w], color=c, ls=d, lw=1.2, label=k)
        ax.set_title(f"Rail deflection at t_end, {cut_title(cut)}")
        ax.set_xlabel("x (m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for row in axes:
        row[0].set_ylabel("w (mm, down)")
    axes[0][0].invert_yaxis()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "deflection.png"), dpi=110)
    plt.close(fig)

    # The paper's Figure 6: error curves per cut x schedule that ran, each run
    # over its own reference.
    def of_panel(k, cut, scheme):
        return cut_of(k) == cut and scheme in k and (scheme != "jacobi" or "gauss" not in k)

    panels = [(cut, scheme) for cut in cuts for scheme in ("jacobi", "gauss-seidel")
              if any(of_panel(k, cut, scheme) for k in usable)]
    ncols = min(2, len(panels))
    nrows = (len(panels) + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(6.5 * ncols, 3.5 * nrows), squeeze=False)
    for k in range(len(panels), nrows * ncols):
        axes[k // ncols][k % ncols].axis("off")
    for n, (cut, scheme) in enumerate(panels):
        ax = axes[n // ncols][n % ncols]
        for k, r in sorted(usable.items()):
            if of_panel(k, cut, scheme):
                x, w = deflection(r["folder"])
                _, w_ref = deflection(reference(r)[0])
                c, d = style(k)
                ax.plot(x, [(a - b) * 1e3 for a, b in zip(w, w_ref)], color=c, ls=d, label=k)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"{cut_title(cut)}, {scheme}")
        ax.set_ylabel("w - w_monolithic (mm)" if reference(usable[next(iter(usable))])[1] == "monolithic"
                      else "w - w_reference (mm)")
        ax.set_xlabel("x (m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "errors.png"), dpi=110)
    plt.close(fig)

    # Contact force: the best run's reference, the best and the worst co-simulation at the scene's H.
    ranked = sorted(usable.values(), key=lambda r: num(r["rel_l2_error"]))
    ref_folder, ref_label = reference(ranked[0])
    fig, ax = plt.subplots(figsize=(11, 4.5))
    t, f = read_xy(os.path.join(study, ref_folder, "history.csv"), "t_s", "contact_force_N")
    ax.plot(t, [v / 1e3 for v in f], "k-", lw=2.5, alpha=0.4, label=ref_label)
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

    spectra(os.path.join(study, ref_folder, "spectra.csv"), out, ref_label)


def map_status(r):
    """A run's cell colour: its status, or "not judged" where its stability
    was not judged (its errors alone do not make it ok)."""
    settled = r["status"] in ("amplified", "diverged", "failed", "not_converged")
    return "not judged" if not settled and r.get("stability") == "not judged" else r["status"]


def rho_digits(rho):
    """rho with three digits in its distance from 1 (at least four in all),
    as the report writes it."""
    off = abs(rho - 1)
    digits = max(4, 3 + math.ceil(-math.log10(off))) if off > 0 else 4
    return "%.*g" % (min(digits, 12), rho)


def map_words(r):
    """A run's cell text: its status, and rho with its rate per second where
    one was measured (matrix-free: through the participants)."""
    words = map_status(r).replace("_", " ")
    rho, rate = r.get("rho", ""), r.get("rho_rate_per_s", "")
    if rho:
        words += "\nρ " + rho_digits(float(rho))
        if rate:
            words += "\n%.3g /s" % float(rate)
        if r.get("rho_basis") == "matrix-free":
            words += " (m-f)"
    return words


def stability_map(runs, out):
    """Macro step against method, grouped by cut (a line between cuts)."""
    methods = []
    for r in runs:
        if r["method"] != "monolithic" and r["group"] in ("case", "sweep") and r["method"] not in methods:
            methods.append(r["method"])
    cuts = list(dict.fromkeys(cut_of(m) for m in methods))
    methods = [m for c in cuts for m in methods if cut_of(m) == c]
    steps = sorted({num(r["macro_step_s"]) for r in runs if r["method"] in methods})
    cells = {(r["method"], num(r["macro_step_s"])): r for r in runs
             if r["method"] in methods and r["group"] in ("case", "sweep")}
    fig, ax = plt.subplots(figsize=(1.2 * len(steps) + 4, 0.55 * len(methods) + 1.8))
    for i, m in enumerate(methods):
        for j, h in enumerate(steps):
            r = cells.get((m, h))
            s = map_status(r) if r else ""
            ax.add_patch(plt.Rectangle((j, i), 1, 1, color=STATUS_COLOURS.get(s, "white"), ec="white"))
            ax.text(j + 0.5, i + 0.5, map_words(r) if r else "not run", ha="center", va="center",
                    fontsize=5.5, color="k" if s else "0.6")
        if i + 1 < len(methods) and cut_of(methods[i + 1]) != cut_of(m):
            ax.axhline(i + 1, color="k", lw=1.5)
    ax.set_xlim(0, len(steps))
    ax.set_ylim(len(methods), 0)
    ax.set_xticks([j + 0.5 for j in range(len(steps))], [f"{h:g}" for h in steps])
    ax.set_yticks([i + 0.5 for i in range(len(methods))], methods, fontsize=8)
    ax.set_xlabel("macro step H (s)")
    # The title over the whole canvas, wrapped to its width (an axes title
    # is centred on the axes, and a long one overflows both sides).
    title = wrapped("Stability map (grouped by cut): green ok; yellow inaccurate (stable, error over its "
                    "bound); orange amplified (unstable: a perturbation of the static state grows); red "
                    "diverged; grey not judged. Each cell: ρ of the macro-step map at rest and its growth rate "
                    "per second (m-f: measured through the participants)", fig.get_figwidth() - 0.4, 10)
    top_in = title_height(title, 10)
    fig.set_figheight(fig.get_figheight() + top_in)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 1 - top_in / fig.get_figheight()))
    fig.savefig(os.path.join(out, "stability_map.png"), dpi=110)
    plt.close(fig)


def spectra(path, out, label):
    """One-third-octave band levels of the reference run (`label`): contact
    forces and the energy mean of the ballast forces over the sleepers (if
    written)."""
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
    ax.set_title(wrapped(f"Force spectra of the {label} run", 10.5, 12))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "spectra.png"), dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    args = sys.argv[1:]
    show = args[:1] == ["--print-front"]
    if show:
        args = args[1:]
    if len(args) != 1:
        sys.exit(__doc__)
    front = main(args[0])
    if show:
        print("cut,level,method,macro_step_s,tolerance_m,wall_s,error,transport")
        for p in front:
            print(",".join(repr(v) if isinstance(v, float) else v for v in p))
