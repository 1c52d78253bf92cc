"""Which soil a scene needs: the same scene's receivers on several soil
models, compared per receiver and one-third-octave band against the most
complete model run, beside what each run cost.

Every number comes from the runs' vibration.csv files (the format of
fe_soil/measures.py), so the comparison can be recomputed from them.
Files written (docs/ground-vibration.md, "Which soil a scene needs"):

- soil_choice.csv: one row per soil, receiver and band:
  soil, receiver_m, band_Hz, level_dB, reference_dB, difference_dB
  (difference = level - reference; the reference's own rows are 0);
- soil_choice.json: {"reference": key, "bands_Hz": [...], "receivers_m": [...],
  "soils": [{"key", "label", "folder", "wall_s", "cpu_s", "parts",
  "max_abs_difference_dB", "rms_difference_dB"}]};
- figures/soil_choice.png: cost (wall s) against the largest |difference|.
"""
import csv
import json
import math
import os

import numpy as np

BAND_PREFIX, BAND_SUFFIX = "Lv_z_", "Hz_dB"


def read_vibration(path):
    """vibration.csv as {distance y_m: {column: float}} (the receiver's name left out)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError("%s: no receiver rows" % path)
    return {float(r["y_m"]): {k: float(v) for k, v in r.items() if k != "receiver"}
            for r in rows}


def band_columns(row):
    """[(column, centre Hz)] of a row's vertical band levels."""
    return [(c, float(c[len(BAND_PREFIX):-len(BAND_SUFFIX)])) for c in row
            if c.startswith(BAND_PREFIX) and c.endswith(BAND_SUFFIX)]


def common_grid(soils):
    """(receivers, bands): the distances every soil has, and the bands whose
    level is finite at each of them in every soil."""
    dists = sorted(set.intersection(*[set(s["vibration"]) for s in soils]))
    if not dists:
        raise ValueError("the soils share no receiver distance (%s)" % "; ".join(
            "%s: %s" % (s["key"], sorted(s["vibration"])) for s in soils))
    first = soils[0]["vibration"][dists[0]]
    bands = [(c, f) for c, f in band_columns(first)
             if all(c in s["vibration"][d] and math.isfinite(s["vibration"][d][c])
                    for s in soils for d in dists)]
    return dists, bands


def compare(soils, reference, fallback=None, resolved=None):
    """soils: [{"key", "label", "folder", "wall_s", "cpu_s", "parts", "vibration"}];
    reference: the key of the most complete run; resolved: {distance: Hz}, the
    highest band centre it is trusted at per receiver (None: every band),
    above which the `fallback` soil is the reference. Returns (rows,
    summary): rows (soil, receiver_m, band_Hz, level, reference level,
    difference, reference key) and the summary soil_choice.json holds."""
    dists, bands = common_grid(soils)
    by_key = {s["key"]: s for s in soils}

    def ref_at(d, f):
        trusted = resolved is None or f <= resolved.get(d, math.inf)
        return reference if trusted or fallback is None else fallback

    rows, out = [], []
    for s in soils:
        diffs = []
        for d in dists:
            for c, f in bands:
                key = ref_at(d, f)
                lv, lr = s["vibration"][d][c], by_key[key]["vibration"][d][c]
                rows.append((s["key"], d, f, lv, lr, lv - lr, key))
                diffs.append(lv - lr)
        diffs = np.array(diffs)
        out.append({k: s[k] for k in ("key", "label", "folder", "wall_s", "cpu_s", "parts")}
                   | {"max_abs_difference_dB": float(np.abs(diffs).max()) if diffs.size else None,
                      "rms_difference_dB": (float(np.sqrt(np.mean(diffs ** 2)))
                                            if diffs.size else None)})
    summary = {"reference": reference, "receivers_m": dists, "bands_Hz": [f for _, f in bands],
               "soils": out}
    if resolved is not None and fallback is not None:
        summary["reference_resolved_Hz"] = [resolved.get(d) for d in dists]
        summary["reference_above"] = fallback
    return rows, summary


def write_data(out, rows, summary):
    with open(os.path.join(out, "soil_choice.csv"), "w") as f:
        f.write("soil,receiver_m,band_Hz,level_dB,reference_dB,difference_dB,reference\n")
        for key, d, band, lv, lr, diff, ref in rows:
            f.write("%s,%.9g,%.9g,%.9g,%.9g,%.9g,%s\n" % (key, d, band, lv, lr, diff, ref))
    with open(os.path.join(out, "soil_choice.json"), "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")


def chart(path, summary):
    """Cost (wall seconds, log) against the largest |difference| from the
    reference; each soil a point labelled with its name and CPU seconds."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for j, s in enumerate(summary["soils"]):
        x, y = s["max_abs_difference_dB"] or 0.0, s["wall_s"]
        ax.semilogy(x, y, marker="os^D"[j % 4], color="C%d" % j, ms=9, ls="none",
                    label="%s: %.3g s wall, %.3g s CPU" % (s["label"], y, s["cpu_s"]))
        ax.annotate(s["label"], (x, y), textcoords="offset points", xytext=(6, 6), fontsize=8)
    ref = next(s["label"] for s in summary["soils"] if s["key"] == summary["reference"])
    ax.annotate("(reference)", (0.0, next(s["wall_s"] for s in summary["soils"]
                                          if s["key"] == summary["reference"])),
                textcoords="offset points", xytext=(6, -12), fontsize=8)
    ax.set_xlabel("largest |level - %s| over receivers and bands (dB)" % ref)
    ax.set_ylabel("cost: wall time of the run (s)")
    ax.set_title("Which soil a scene needs: cost against difference", fontsize=10)
    top = max(s["max_abs_difference_dB"] or 0.0 for s in summary["soils"])
    ax.set_xlim(-0.05 * max(top, 0.1), 1.3 * max(top, 0.1))
    walls = [s["wall_s"] for s in summary["soils"]]
    ax.set_ylim(min(walls) / 3.0, max(walls) * 3.0)  # at least a decade: readable ticks
    ax.yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def section(rows, summary):
    """The report's section "## Which soil a scene needs" (markdown lines)."""
    soils = summary["soils"]
    label = {s["key"]: s["label"] for s in soils}
    ref = label[summary["reference"]]
    L = ["## Which soil a scene needs", "",
         "Each soil model's vertical one-third-octave levels minus those of the reference, per "
         "receiver and band (dB), and the cost of each run: wall and CPU seconds of its "
         "processes on this machine. The reference is the most complete model run (%s)%s. "
         "Bands: those with a finite level at every receiver in every run. Data: "
         "`soil_choice.csv`, `soil_choice.json`; chart: `figures/soil_choice.png`."
         % (ref, resolution_note(summary, label)), "",
         "### Cost and largest difference", "",
         "| soil | what runs | wall (s) | CPU (s) | max abs difference (dB) | RMS difference (dB) |",
         "|---|---|---:|---:|---:|---:|"]
    for s in soils:
        what = "; ".join("%s %.1f s" % (k, v) for k, v in s["parts"].items())
        L.append("| %s | %s | %.2f | %.2f | %s | %s |" % (
            s["label"], what, s["wall_s"], s["cpu_s"], fmt(s["max_abs_difference_dB"]),
            fmt(s["rms_difference_dB"])))
    for d in summary["receivers_m"]:
        L += ["", "### %g m: level minus the reference (dB)" % d, "",
              "| band (Hz) | reference | reference (dB) | %s |" % " | ".join(
                  "%s - reference" % s["label"] for s in soils),
              "|---:|---|---:|" + "---:|" * len(soils)]
        at = {(k, f): (lr, diff, rk) for k, dd, f, _, lr, diff, rk in rows if dd == d}
        for f in summary["bands_Hz"]:
            lr, _, rk = at[(soils[0]["key"], f)]
            L.append("| %.3g | %s | %.2f | %s |" % (f, label[rk], lr, " | ".join(
                "%+.2f" % at[(s["key"], f)][1] for s in soils)))
    return L


def resolution_note(summary, label):
    if "reference_resolved_Hz" not in summary:
        return ""
    fs = summary["reference_resolved_Hz"]
    where = ", ".join("%.3g Hz at %g m" % (f, d) for f, d in zip(fs, summary["receivers_m"]))
    return (" up to the band its mesh resolves (10 elements per Rayleigh wavelength of the "
            "softest layer: %s); above it the reference is the %s soil, and the %s rows "
            "show the mesh's difference from it" % (where, label[summary["reference_above"]],
                                                   label[summary["reference"]]))


def fmt(x):
    return "-" if x is None else "%.2f" % x
