"""The levels of the vibration on the scene's ground shapes against the flat
ground (fe_soil/ground_shapes.py), by the insertion-loss study's command:

    /usr/bin/python3 -m fe_soil.mitigation --grounds --scene SCENE --out DIR

Runs the scene's FE soil on the flat ground ("at_grade") and on each
[[soil.grounds]] entry, without any path measure, under the load of
[soil.mitigation] and at the receivers of [soil] receivers (distances from
the track's centre line; each on the ground's surface at its distance),
and writes

- DIR/ground_levels.csv: per ground and receiver the one-third-octave
  levels L_v of the vertical velocity (dB re 1e-9 m/s) from 1 to 80 Hz,
  its PPV (m/s), KB_Fmax and the overall level (dB), and the difference
  to the flat ground (dB; positive: lower than at grade);
- DIR/REPORT.md: a table of levels per ground, and the differences;
- DIR/figures/ground_difference.png: L_at_grade - L_ground against band;
- DIR/runs/GROUND/receivers.npz: each run's record, in full precision.
"""
import math
import os

import numpy as np

from . import config as fe_config
from . import ground_shapes, mitigation, path_measures, resolution, study_load
from .soil_table import ConfigError


def ground_block(cfg, fps, ground):
    """SoilParams of the scene's block on that ground, without any measure."""
    return fe_config.block_params(dict(cfg, ground=ground, variant=path_measures.REFERENCE),
                                  fps)[0]


def csv_text(names, distances, fc, lv, diff):
    rows = ["ground,receiver,distance_m,quantity,band_hz,value,difference_dB"]
    for g, per in lv.items():
        for k, (rec, d) in enumerate(zip(names, distances)):
            il = diff[g][k]
            for i, f in enumerate(fc):
                x, y = per[k]["lv"][i], il["band"][i]
                rows.append("%s,%s,%g,band_dB,%.4g,%s,%s" % (
                    g, rec, d, f, "%.4f" % x if math.isfinite(x) else "",
                    "%.4f" % y if math.isfinite(y) else ""))
            for q, key, fmt in (("ppv_mps", "ppv", "%.6e"), ("kb_fmax", "kb", "%.6e"),
                                ("overall_dB", "overall", "%.4f")):
                dq = {"ppv": "ppv", "kb": "kb_fmax", "overall": "overall"}[key]
                rows.append("%s,%s,%g,%s,,%s,%.4f" % (g, rec, d, q, fmt % per[k][key], il[dq]))
    return "\n".join(rows) + "\n"


def report(path, info, fc, lv, diff):
    load = info["load"]
    lines = ["# Vibration levels on the ground shapes: %s" % info["name"], "",
             "One-third-octave levels L_v of the vertical velocity (dB re 1e-9 m/s) at each "
             "receiver, on the flat ground and on each shape, under one load: %s; "
             "receivers at equal distances from the track's centre line, each on the ground's "
             "surface there. Difference: L_at_grade - L_ground (positive: lower than at grade), "
             "judged where the flat ground's mesh resolves the band at the receiver. PPV and "
             "the overall level: the record low-passed at the frequency that mesh resolves "
             "there (%s)." % (load, mitigation.lowpass_text(
                 info["receivers"], next(iter(diff.values())))), ""]
    for g, per in lv.items():
        shape = info["grounds"][g]
        lines += ["## %s: %s (%d DOFs)" % (g, shape.shape.replace("_", " "), info["dofs"][g]), "",
                  "| band (Hz) | " + " | ".join("%s (z %+.2f m)" % (r, z) for r, z in
                                               zip(info["receivers"], info["heights"][g])) + " |",
                  "|---:|" + "---:|" * len(per)]
        for i, f in enumerate(fc):
            if any(math.isfinite(diff[g][k]["band"][i]) for k in range(len(per))):
                lines.append("| %.3g | %s |" % (f, " | ".join(
                    "%.1f (%+.1f)" % (p["lv"][i], d["band"][i]) if math.isfinite(d["band"][i])
                    else "%.1f" % p["lv"][i] for p, d in zip(per, diff[g]))))
        lines.append("| overall | %s |" % " | ".join(
            "%.1f (%+.1f)" % (p["overall"], d["overall"]) for p, d in zip(per, diff[g])))
        lines.append("| PPV (mm/s) | %s |" % " | ".join(
            "%.3g (%+.1f dB)" % (1e3 * p["ppv"], d["ppv"]) for p, d in zip(per, diff[g])))
        lines.append("")
    lines += ["![Difference to the flat ground per band](figures/ground_difference.png)", ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def sources(scene, load, cfg, grounds, master, out, scene_dir):
    """The load per ground: one Ricker force for all; a train's forces from
    each ground's own block, which carries the track (fe_soil/study_load.py)."""
    from .model import FESoil

    if load["load"] != "train":
        one = study_load.make(scene, load, cfg, None, master, out, scene_dir)
        return {g: one for g in grounds}
    return {g: study_load.make(scene, load, cfg,
                               lambda fps, g=g: FESoil(ground_block(cfg, fps, g)), master,
                               os.path.join(out, "train", g), scene_dir) for g in grounds}


def load_text(per):
    """The report's sentence on the load."""
    first = next(iter(per.values()))
    if not isinstance(first, study_load.Train):
        return first.text()
    return ("%s; each ground's forces from its own track: the lumped soil fitted to that "
            "ground's block (k_f %s N/m)" % (first.text(), ", ".join(
                "%s %.4g" % (g, src.kf) for g, src in per.items())))


def study(scene, out, name="scene", master=None, scene_dir="."):
    """Runs the flat ground and every listed ground; writes the outputs.
    master: the master program, for a train load (fe_soil/study_load.py);
    scene_dir: the folder of the scene's relative file names."""
    from .model import FESoil

    cfg = fe_config.parse(scene["soil"])
    load = mitigation.load_keys(scene["soil"].get("mitigation"))
    if not cfg["grounds"]:
        raise ConfigError("[soil] grounds: the scene lists none ([[soil.grounds]]): there is "
                          "nothing to compare with the flat ground")
    grounds = [ground_shapes.AT_GRADE] + [g.name for g in cfg["grounds"]]
    per = sources(scene, load, cfg, grounds, master, out, scene_dir)
    records, dofs, heights, bands = {}, {}, {}, None
    for g in grounds:
        print("ground: %s" % g, flush=True)
        source = per[g]
        soil = FESoil(ground_block(cfg, source.footprints, g))
        t, vel = source.drive(soil)
        records[g], dofs[g] = vel, soil.global_dofs()
        heights[g] = list(soil.rec_points[:, 2])
        os.makedirs(os.path.join(out, "runs", g), exist_ok=True)
        np.savez(os.path.join(out, "runs", g, "receivers.npz"), t=t, v=vel,
                 z=soil.rec_points[:, 2])
        if bands is None:  # the flat ground's mesh judges the bands
            bands = resolution.receiver_bands(soil, cfg, load["duration"])
            tops = resolution.resolved_frequencies(soil, cfg)
    names = [c[: -len("_vz_mps")] for c in fe_config.channel_names(cfg["receivers"])]
    lv = {g: mitigation.levels(records[g], source.dt, tops) for g in grounds}
    ref = lv[ground_shapes.AT_GRADE]
    diff = {g: mitigation.insertion_loss(ref, lv[g], bands) for g in grounds}
    fc = ref[0]["fc"]
    with open(os.path.join(out, "ground_levels.csv"), "w") as f:
        f.write(csv_text(names, cfg["receivers"], fc, lv, diff))
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    mitigation.figure(os.path.join(out, "figures", "ground_difference.png"), names, fc,
                      {g: diff[g] for g in grounds[1:]})
    info = {"name": name, "load": load_text(per), "receivers": names, "dofs": dofs,
            "heights": heights,
            "grounds": {g: ground_shapes.find(cfg["grounds"], g) for g in grounds}}
    report(os.path.join(out, "REPORT.md"), info, fc, lv, diff)
    return records, lv, diff
