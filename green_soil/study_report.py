"""REPORT.md of green_soil.study, from the runs' files: the levels at every
receiver (the reference run's vibration.csv), which soil the scene needs
(green_soil/soil_choice.py), the check of the one-way machinery, the files."""
import math
import os

from fe_soil import study_report as fe_report

from . import resolution, soil_choice

# Relative to the peak: the same convolution, read back from receivers.csv,
# which holds 9 significant digits (5e-10 of a value).
ONE_WAY_BOUND = 1e-8
TESTS_HEADING = "### The soil from Green's functions"


def levels(soils, summary, resolved):
    key = summary.get("reference_above", summary["reference"])
    ref = next(s for s in soils if s["key"] == key)
    d = summary["receivers_m"]
    why = ("" if key == summary["reference"] else
           " PPV and KB_Fmax take every band, and the FE mesh resolves only the lowest "
           "(below): these are the %s soil's." % ref["label"])
    L = ["## Levels at the receivers (%s)" % ref["label"], "",
         "Vertical velocity on the surface beside the middle of the track. PPV_z (m/s), "
         "KB_Fmax,z (DIN 4150-2) and the one-third-octave levels (dB re 1e-9 m/s) of "
         "`%s/vibration.csv`.%s Resolved: the one-third-octave bands (their centres, Hz) "
         "the Green's-function soil resolves at the receiver (green_soil/resolution.py)."
         % (ref["folder"], why), "",
         "| distance | PPV_z (m/s) | KB_Fmax,z | resolved (Hz) | resolved from / to: limited by |",
         "|---:|---:|---:|---:|---|"]
    for x, res in zip(d, resolved):
        r = ref["vibration"][x]
        L.append("| %g m | %.4e | %.4g | %s | %s / %s |" % (
            x, r["ppv_z_mps"], r["kb_fmax_z"], resolution.cell(res), res["lo_why"],
            res["hi_why"]))
    empty = [f for c, f in soil_choice.band_columns(ref["vibration"][d[0]])
             if any(not math.isfinite(ref["vibration"][x][c]) for x in d)]
    if empty:
        L += ["", "Bands with no spectral line in this record, written as -inf in "
              "`vibration.csv` and left out of the comparison below: %s Hz. A band's "
              "lines are 1/T apart in a record of T s; a longer `[simulation] end_time` "
              "fills them." % ", ".join("%.3g" % f for f in empty)]
    return L


def check(fit):
    err = fit["one_way_error"]
    return ["## Validation", "", "### Checks run by this study", "",
            "| check | bound | measured | result |", "|---|---|---|---|",
            "| the one-way pass under the Green's-function run's own ballast forces (held "
            "over each step) against that run's receivers, largest difference / peak | "
            "<= %.0e | %.1e | %s |" % (ONE_WAY_BOUND, err,
                                       "pass" if err <= ONE_WAY_BOUND else "**FAIL**")]


def write(out, a, scene, soils, rows, summary, fit, resolved):
    name = scene.get("scene", {}).get("name", a.scene)
    L = ["# Which soil a scene needs: %s" % name, "",
         "Scene `%s`. Written by `python3 -m green_soil.study`. Record %.4g s, sampled every "
         "macro step of the soil (%.3g s). Soils run: %s. The lumped soil is fitted to the layered "
         "ground's static flexibility under the footprints (k_f = %.4g N/m, k_c = %.4g N/m); "
         "its ballast forces reach the receivers one way through the Green's functions.%s" % (
             os.path.basename(a.scene), scene["simulation"]["end_time"],
             scene.get("coupling", {}).get("ss_macro_step", scene["simulation"]["macro_step"]), ", ".join(s["label"] for s in soils),
             fit["kf"], fit["kc"],
             "" if a.fe else " The FE soil was not run (`--fe` not given)."), ""]
    L += levels(soils, summary, resolved) + [""] + soil_choice.section(rows, summary) + [""]
    L += ["## Figures", "",
          "- `figures/soil_choice.png`: each soil's cost (wall s) against its largest "
          "|difference| from the reference over the receivers and bands", ""]
    L += check(fit) + ["", "### The Green's-function soil's tests", ""] + fe_report.tests_table(TESTS_HEADING, "green_soil")
    L += ["", "## Files", "",
          "- `soil_choice.csv`, `soil_choice.json`: the comparison's data "
          "(docs/ground-vibration.md, \"Which soil a scene needs\")",
          "- %s: the two-way runs' files" % ", ".join(
              "`%s/`" % s["folder"] for s in soils if s["key"] != "lumped"),
          "- `runs/lumped/monolithic/`: the lumped soil's run and its `soil_forces.csv`; "
          "`lumped.toml` its scene; `runs/two-step/`: its receivers one way", ""]
    with open(os.path.join(out, "REPORT.md"), "w") as f:
        f.write("\n".join(L))
