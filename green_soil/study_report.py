"""REPORT.md of green_soil.study, from the runs' files: the levels at every
receiver (the reference run's vibration.csv), which soil the scene needs
(green_soil/soil_choice.py), the check of the one-way machinery, the files."""
import os

from . import soil_choice

# Relative to the peak: the same convolution, read back from receivers.csv,
# which holds 9 significant digits (5e-10 of a value).
ONE_WAY_BOUND = 1e-8


def levels(soils, summary):
    ref = next(s for s in soils if s["key"] == summary["reference"])
    d = summary["receivers_m"]
    L = ["## Levels at the receivers (%s)" % ref["label"], "",
         "Vertical velocity on the surface beside the middle of the track. PPV_z (m/s), "
         "KB_Fmax,z (DIN 4150-2) and the one-third-octave levels (dB re 1e-9 m/s) of "
         "`%s/vibration.csv`." % ref["folder"], "",
         "| distance | PPV_z (m/s) | KB_Fmax,z |", "|---:|---:|---:|"]
    for x in d:
        r = ref["vibration"][x]
        L.append("| %g m | %.4e | %.4g |" % (x, r["ppv_z_mps"], r["kb_fmax_z"]))
    return L


def check(fit):
    err = fit["one_way_error"]
    return ["## Check", "",
            "| check | bound | measured | result |", "|---|---|---|---|",
            "| the one-way pass under the Green's-function run's own ballast forces (held "
            "over each step) against that run's receivers, largest difference / peak | "
            "<= %.0e | %.1e | %s |" % (ONE_WAY_BOUND, err,
                                       "pass" if err <= ONE_WAY_BOUND else "**FAIL**")]


def write(out, a, scene, soils, rows, summary, fit):
    name = scene.get("scene", {}).get("name", a.scene)
    L = ["# Which soil a scene needs: %s" % name, "",
         "Scene `%s`. Written by `python3 -m green_soil.study`. Record %.4g s, sampled every "
         "macro step (%.3g s). Soils run: %s. The lumped soil is fitted to the layered "
         "ground's static flexibility under the footprints (k_f = %.4g N/m, k_c = %.4g N/m); "
         "its ballast forces reach the receivers one way through the Green's functions.%s" % (
             os.path.basename(a.scene), scene["simulation"]["end_time"],
             scene["simulation"]["macro_step"], ", ".join(s["label"] for s in soils),
             fit["kf"], fit["kc"],
             "" if a.fe else " The FE soil was not run (`--fe` not given)."), ""]
    L += levels(soils, summary) + [""] + soil_choice.section(rows, summary) + [""]
    L += ["## Figures", "",
          "- `figures/soil_choice.png`: each soil's cost (wall s) against its largest "
          "|difference| from the reference over the receivers and bands", ""]
    L += check(fit)
    L += ["", "## Files", "",
          "- `soil_choice.csv`, `soil_choice.json`: the comparison's data "
          "(docs/ground-vibration.md, \"Which soil a scene needs\")",
          "- %s: the two-way runs' files" % ", ".join(
              "`%s/`" % s["folder"] for s in soils if s["key"] != "lumped"),
          "- `runs/lumped/monolithic/`: the lumped soil's run and its `soil_forces.csv`; "
          "`lumped.toml` its scene; `runs/two-step/`: its receivers one way", ""]
    with open(os.path.join(out, "REPORT.md"), "w") as f:
        f.write("\n".join(L))
