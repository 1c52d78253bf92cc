"""The speed/accuracy chart of a study (figures.py draws it with the other
figures): one panel per cut, every method over the macro-step sweep against
the monolithic tolerance sweep, and the report's answer (front.csv) as
numbered stars with a table of them. Also what both modules read from a
study's CSV files: its rows, numbers, and the cut of a method label.
"""
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from figure_text import fit_legend, place_labels, title_height, wrapped  # noqa: E402

RAN_TO_END = ("ok", "inaccurate", "amplified")  # judged against the monolithic run


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(text):
    return float(text) if text not in ("", "null") else math.nan


# Colour by method family, line by schedule, marker by transport.
FAMILIES = (
    ("explicit, held inputs", "#1f77b4"),
    ("explicit, extrapolated inputs", "#ff7f0e"),
    ("implicit (IQN-ILS)", "#2ca02c"),
    ("substep waveforms", "#9467bd"),
)
MARKERS = {"tcp": "o", "inproc": "s"}
CUT_NAMES = {"wr": "wheel/rail", "rs": "rail/sleepers", "ss": "sleepers/soil"}


def family(method):
    if "waveform" in method or "substep" in method:
        return FAMILIES[3]
    if "+implicit" in method:
        return FAMILIES[2]
    if "extrapolate" in method:
        return FAMILIES[1]
    return FAMILIES[0]


def dash(method):
    return "--" if "gauss-seidel" in method else "-"


def cut_of(method):
    """The cut of a method label, as the report names it: wr-xt-jacobi -> wr,
    wr-xx+ss-xt-gauss-seidel -> wr+ss (report_front.cpp's cut_of)."""
    if method == "monolithic":
        return method
    ends = [i for i in (method.find("-jacobi"), method.find("-gauss-seidel")) if i >= 0]
    base = method[: min(ends)] if ends else method
    return "+".join(p[:2] for p in base.split("+"))


def short_name(method, cut):
    """The method without its cut(s), for labels inside the cut's panel."""
    name = method.replace("gauss-seidel", "GS").replace("jacobi", "J")
    name = name.replace("+implicit-linear-iqn-ils", " implicit").replace("+explicit-extrapolate1", " extrap.")
    name = name.replace("+implicit-waveform", " implicit wf").replace("-iqn-ils", "")
    return name if "+" in cut else name[len(cut) + 1:]


def read_front(study):
    path = os.path.join(study, "front.csv")
    return read_rows(path) if os.path.exists(path) else []


def speed_accuracy(study, runs, out):
    """One panel per cut: every method of the cut over the macro-step sweep,
    the monolithic tolerance sweep as reference, and the report's answer
    (front.csv) as numbered stars, each number a row of the answer table
    under the panels. Returns the front drawn."""
    front = read_front(study)
    cosim = [r for r in runs if r["group"] in ("case", "sweep", "other-transport") and r["method"] != "monolithic"]
    cuts = []
    for r in cosim:
        if cut_of(r["method"]) not in cuts:
            cuts.append(cut_of(r["method"]))
    levels = sorted({num(f["level"]) for f in front}, reverse=True) or [1e-3, 1e-4, 1e-5]
    ncols = 1 if len(cuts) == 1 else 2
    nrows = max(1, math.ceil(len(cuts) / ncols))
    answers = sum(1 for f in front if f["method"] and f["cut"] in cuts)
    table_h = 0.24 * (answers + 1) + 0.2  # inches: a row per answer and the header
    fig = plt.figure(figsize=(7.5 * ncols, 5.2 * nrows + table_h + 0.6))
    grid = fig.add_gridspec(nrows + 1, ncols, height_ratios=[5.2] * nrows + [table_h])
    axes = [[None] * ncols for _ in range(nrows)]
    for k in range(nrows * ncols):
        first = axes[0][0]
        axes[k // ncols][k % ncols] = fig.add_subplot(grid[k // ncols, k % ncols], sharex=first, sharey=first)
    tol = sorted(  # along the tolerance, loosest first
        (num(r["wall_s"]), num(r["rel_l2_error_converged"]), r["tolerance_m"], r["transport"])
        for r in runs
        if r["method"] == "monolithic" and r["group"] in ("tolerance", "case") and r["status"] == "ok"
        and num(r["rel_l2_error_converged"]) > 0
    )
    tol = sorted(dict((t[2], t) for t in tol).values(), key=lambda t: -float(t[2]))
    state = {"drawn": [], "families": set(), "unstable": False, "answers": [], "labels": []}
    for k, cut in enumerate(cuts):
        panel(axes[k // ncols][k % ncols], cut, cosim, tol, front, levels, state)
    for k in range(len(cuts), nrows * ncols):
        axes[k // ncols][k % ncols].axis("off")
    against = ("the co-simulation reference" if any(r.get("reference_kind") == "co-simulation" for r in cosim)
               else "the converged monolithic run")
    for row in axes:
        row[0].set_ylabel(f"rel. L2 error of the deflection at t_end\n(against {against})")
    for ax in axes[-1]:
        ax.set_xlabel("wall time (s)")
    answer_table(fig.add_subplot(grid[nrows, :]), state["answers"])
    # The legend and the title take what they need of the canvas's height;
    # the labels are placed once the panels have their size.
    _, legend_in = legend(fig, state, cosim, tol)
    title = wrapped("Speed against accuracy, per cut: each point a macro step H; "
                    "a numbered star is the method to use (table below)", fig.get_figwidth() - 0.4, 12)
    top_in = title_height(title, 12)
    fig.set_figheight(fig.get_figheight() + legend_in + top_in)
    fig.suptitle(title, fontsize=12)
    h = fig.get_figheight()
    fig.tight_layout(rect=(0, (legend_in + 0.1) / h, 1, 1 - top_in / h))
    place_labels(fig, state["labels"])
    fig.savefig(os.path.join(out, "speed_accuracy.png"), dpi=110)
    plt.close(fig)
    return state["drawn"]


def answer_table(ax, answers):
    """The answer as a table: one row per numbered star."""
    ax.axis("off")
    if not answers:
        ax.text(0.5, 0.5, "no co-simulation reaches any error level", ha="center", va="center", fontsize=9)
        return
    rows = [[str(n), cut, f"\u2264 {levels}", method, f"{h:g}", f"{x:.3g}", transport]
            for n, cut, levels, method, h, x, transport in answers]
    t = ax.table(cellText=rows, colLabels=["#", "cut", "error", "method to use", "H (s)", "wall (s)", "over"],
                 loc="upper center", cellLoc="left", colLoc="left", edges="horizontal")
    t.auto_set_font_size(False)
    t.set_fontsize(8.5)
    t.auto_set_column_width(list(range(7)))
    for (r, _), cell in t.get_celld().items():
        cell.set_height(1.0 / (len(rows) + 1))
        if r == 0:
            cell.set_text_props(fontweight="bold")


def panel(ax, cut, cosim, tol, front, levels, state):
    """One cut's panel of the speed/accuracy chart; the front it draws goes
    to state["drawn"] (each point where summary.csv puts it)."""
    by_folder = {r["folder"]: r for r in cosim}
    if tol:
        ax.plot([t[0] for t in tol], [t[1] for t in tol], "k-", lw=2.5, alpha=0.8, zorder=4)
        for t in tol:
            ax.plot(t[0], t[1], MARKERS.get(t[3], "o"), color="k", ms=5, zorder=4)
            ax.annotate(f"tol {float(t[2]):g}", (t[0], t[1]), fontsize=6, xytext=(-4, -9),
                        textcoords="offset points", ha="right")
    for lv in levels:
        ax.axhline(lv, color="0.5", lw=0.8, ls=":", zorder=1)
    chosen = {f["method"] for f in front if f["cut"] == cut and f["method"]}
    diverged = 0
    for m in dict.fromkeys(r["method"] for r in cosim if cut_of(r["method"]) == cut):
        mine = [r for r in cosim if r["method"] == m]
        diverged += sum(r["status"] == "diverged" for r in mine)
        pts = sorted(  # along the macro step, largest first
            (num(r["wall_s"]), num(r["rel_l2_error_converged"]), r["status"], r["transport"], r["group"],
             num(r["macro_step_s"]))
            for r in mine
            if r["status"] in RAN_TO_END and num(r["rel_l2_error_converged"]) > 0
        )
        if not pts:
            continue
        name, colour = family(m)
        state["families"].add(name)
        bold = m in chosen
        pts.sort(key=lambda p: -p[5])
        line = [p for p in pts if p[4] != "other-transport"]
        ax.plot([p[0] for p in line], [p[1] for p in line], color=colour, ls=dash(m),
                lw=2.6 if bold else 1.0, alpha=1.0 if bold else 0.55, zorder=3 if bold else 2)
        for p in pts:
            mk = MARKERS.get(p[3], "o")
            if p[2] in ("ok", "inaccurate"):  # stable
                ax.plot(p[0], p[1], mk, color=colour, ms=4, zorder=3)
            else:
                state["unstable"] = True
                ax.plot(p[0], p[1], mk, ms=11, mfc="none", mec="#d50000", mew=2, zorder=5)
        first = min(line or pts)
        state["labels"].append((ax, short_name(m, cut), first[0], first[1],
                                dict(fontsize=6.5, color=colour, fontweight="bold" if bold else "normal")))
    # The front: the report's answer, each point where summary.csv puts it.
    labels = {}
    for f in front:
        if f["cut"] != cut or not f["method"]:
            continue
        r = by_folder[f["folder"]]
        x, y = num(r["wall_s"]), num(r["rel_l2_error_converged"])
        state["drawn"].append((cut, num(f["level"]), r["method"], num(r["macro_step_s"]), num(r["tolerance_m"]), x, y,
                               r["transport"]))
        labels.setdefault((x, y, r["method"], num(r["macro_step_s"]), r["transport"]), []).append(
            f"{num(f['level']):g}")
    for (x, y, m, h, t), lv in labels.items():
        n = len(state["answers"]) + 1
        state["answers"].append((n, cut, ", ".join(lv), m, h, x, t))
        ax.plot(x, y, "*", ms=18, color="gold", mec="k", mew=1.2, zorder=8)
        ax.annotate(str(n), (x, y), fontsize=9, fontweight="bold", xytext=(7, 5), textcoords="offset points",
                    ha="left", va="bottom", zorder=9,
                    bbox=dict(boxstyle="circle,pad=0.15", fc="white", ec="k", lw=0.8))
    several = len({f.get("transport", "") for f in front if f["cut"] == cut}) > 1
    missing = [f"{num(f['level']):g}" + (f" over {f['transport']}" if several else "")
               for f in front if f["cut"] == cut and not f["method"]]
    note = []
    if diverged:
        note.append(f"{diverged} diverged runs not drawn")
    if missing:
        note.append("nothing reaches " + ", ".join(missing))
    if note:
        ax.text(0.99, 0.01, "; ".join(note), transform=ax.transAxes, ha="right", va="bottom", fontsize=7,
                color="0.3")
    title = " + ".join(CUT_NAMES.get(c, c) for c in cut.split("+"))
    ax.set_title(f"{cut}: {title} cut", fontsize=11)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.grid(alpha=0.25, which="both")


def legend(fig, state, cosim, tol):
    """At most 8 entries: the families drawn, the reference, the schedules,
    the unstable points and the answer; the transports in its title. As
    many columns (up to 4) as the canvas's width holds; returns the legend
    and its height in inches."""
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], color=c, lw=2, label=n) for n, c in FAMILIES if n in state["families"]]
    handles += [
        Line2D([], [], color="k", lw=2.5, marker="s", label="monolithic, tolerance sweep (reference)"),
        Line2D([], [], color="0.3", ls="-", label="Jacobi"),
        Line2D([], [], color="0.3", ls="--", label="Gauss\u2013Seidel"),
    ]
    if state["unstable"]:
        handles.append(Line2D([], [], ls="", marker="o", ms=11, mfc="none", mec="#d50000", mew=2,
                              label="amplified (unstable)"))
    handles.append(Line2D([], [], ls="", marker="*", ms=16, color="gold", mec="k",
                          label="the answer, numbered as in the table: cheapest to reach each error level"))
    transports = sorted({r["transport"] for r in cosim} | {t[3] for t in tol})
    return fit_legend(fig, 4, handles=handles, loc="lower center", fontsize=8, frameon=False,
               title="markers: " + ", ".join(f"{MARKERS.get(t, 'o').replace('o', 'circle').replace('s', 'square')} "
                                             f"{t}" for t in transports) + "; dotted lines: the error levels",
               title_fontsize=8)
