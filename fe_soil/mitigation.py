"""The insertion loss of the path measures of a scene's FE soil.

    /usr/bin/python3 -m fe_soil.mitigation --scene SCENE --out DIR
    /usr/bin/python3 -m fe_soil.mitigation --grounds --scene SCENE --out DIR

The second form compares the ground shapes instead (fe_soil/ground_study.py).

Runs the scene's FE soil ([soil] model = "fe") once without any measure
(the reference) and once with each [[soil.measures]] entry alone, under the
same load and at the same receivers, and writes

- DIR/insertion_loss.csv: per measure and receiver the insertion loss
  IL = L_ref - L_measure (dB; positive: the measure reduces the vibration)
  of the vertical velocity in each one-third-octave band from 1 to 80 Hz,
  of its PPV and KB_Fmax (20 log10 of the ratio) and of its overall level
  (the bands' energies summed), these three of the record low-passed at
  the frequency the mesh resolves at the receiver;
- DIR/REPORT.md: a table per measure, and where a measure amplifies (IL < 0);
- DIR/figures/insertion_loss.png: IL against band, a line per measure and
  receiver;
- DIR/runs/VARIANT/receivers.npz: each run's record (t, v[time, receiver,
  component]), in full precision.

The load is that of [soil.mitigation] (the FE soil ignores the table): a
Ricker force on the middle footprint, or the scene's train on its track
(load = "train", run by the master program given with --master), the same
for every variant: fe_soil/study_load.py.

A band is judged where the soil resolves it at the receiver
(resolution.receiver_bands) and the reference's level lies within
CONTENT_DB of its highest band; elsewhere its IL is left empty.
"""
import argparse
import math
import os
import sys

import numpy as np

from .scene_file import read_scene
from . import config as fe_config
from . import measures, path_measures, resolution, study_load, two_step
from .soil_table import ConfigError
from .study_load import load_keys  # noqa: F401  (the studies' keys, read here too)

BAND_TOP = 80.0  # Hz, the highest band centre reported
CONTENT_DB = 40.0  # bands more than this below the reference's highest are not judged


def footprints(scene, n):
    """n footprints at the scene's sleeper spacing from x = 0 (one rail's
    half, as the ss cut sends them: fe_soil/two_step.py)."""
    spacing = scene["sleepers"]["spacing"]
    return two_step.footprints(scene, [spacing * i for i in range(n)])


def variant_block(cfg, fps, variant):
    """SoilParams of the scene's block with the measures of `variant`."""
    return fe_config.block_params(dict(cfg, variant=variant), fps)[0]


def levels(v, dt, tops):
    """Per receiver: band centres, vertical band levels (1-80 Hz) of v_z,
    and its PPV, KB_Fmax and overall level (the bands' energies summed) of
    v_z low-passed at tops[k], the frequency the mesh resolves there
    (measures.low_passed; the bands are judged by insertion_loss)."""
    out = []
    for k, top in zip(range(v.shape[1]), tops):
        vz = v[:, k, 2]
        fc, rms = measures.band_rms(vz, dt, 1.0, BAND_TOP)
        lp = measures.low_passed(vz, dt, top)
        _, rms_lp = measures.band_rms(lp, dt, 1.0, BAND_TOP)
        with np.errstate(divide="ignore"):
            lv = 20.0 * np.log10(rms / measures.V_REF)
            overall = 10.0 * np.log10(np.sum(rms_lp**2)) - 20.0 * math.log10(measures.V_REF)
        out.append({"fc": fc, "lv": lv, "ppv": measures.ppv(lp), "kb": measures.kb_fmax(lp, dt),
                    "overall": overall, "lowpass_hz": top})
    return out


def insertion_loss(ref, var, bands):
    """Per receiver {band: IL per band (nan where not judged), ppv, kb_fmax,
    overall} = reference minus measure (dB); bands: the (lowest, highest)
    resolved band centre per receiver."""
    out = []
    for r, m, (lo, hi) in zip(ref, var, bands):
        ok = (r["fc"] >= lo * (1 - 1e-6)) & (r["fc"] <= hi * (1 + 1e-6))
        ok &= np.isfinite(r["lv"]) & (r["lv"] >= np.max(r["lv"][np.isfinite(r["lv"])]) - CONTENT_DB)
        with np.errstate(invalid="ignore"):
            band = np.where(ok, r["lv"] - m["lv"], math.nan)
        out.append({"band": band, "ppv": 20.0 * math.log10(r["ppv"] / m["ppv"]),
                    "kb_fmax": 20.0 * math.log10(r["kb"] / m["kb"]),
                    "overall": r["overall"] - m["overall"], "lowpass_hz": r["lowpass_hz"]})
    return out


def csv_text(names, distances, fc, losses):
    """insertion_loss.csv: measure, receiver, distance_m, quantity (band,
    ppv, kb_fmax, overall), band_hz (the centre; empty but for bands),
    IL_dB (empty where not judged)."""
    rows = ["measure,receiver,distance_m,quantity,band_hz,IL_dB"]
    for name, per in losses.items():
        for rec, d, il in zip(names, distances, per):
            for f, x in zip(fc, il["band"]):
                rows.append("%s,%s,%g,band,%.4g,%s" % (name, rec, d, f,
                                                        "" if math.isnan(x) else "%.4f" % x))
            for q in ("ppv", "kb_fmax", "overall"):
                rows.append("%s,%s,%g,%s,,%.4f" % (name, rec, d, q, il[q]))
    return "\n".join(rows) + "\n"


def amplifications(names, fc, per):
    """A sentence naming where a measure's IL < 0 (bands and measures)."""
    where = []
    for rec, il in zip(names, per):
        bands = [f for f, x in zip(fc, il["band"]) if x < 0.0]
        whole = [q for q in ("ppv", "kb_fmax", "overall") if il[q] < 0.0]
        if bands or whole:
            worst = min([x for x in il["band"] if x < 0.0] + [il[q] for q in whole])
            where.append("%s (%s; down to %.1f dB)" % (
                rec, ", ".join(["%.3g Hz" % f for f in bands] + whole), worst))
    return ("It amplifies (IL < 0) at " + "; ".join(where) + "." if where else
            "It amplifies nowhere: IL >= 0 in every judged band and measure.")


def lowpass_text(names, per):
    """'r3m 24.1 Hz, r6m 22.0 Hz' (unfiltered where nothing is resolved)."""
    return ", ".join("%s %.3g Hz" % (n, il["lowpass_hz"]) if il["lowpass_hz"] > 0.0 else
                     "%s unfiltered (nothing resolved)" % n for n, il in zip(names, per))


def report(path, info, fc, losses):
    lines = ["# Insertion loss of the path measures: %s" % info["name"], "",
             "IL = L_ref - L_measure in dB, the vertical velocity at each receiver: positive "
             "where the measure reduces the vibration, negative where it amplifies. The "
             "reference is the scene's FE soil without any measure; each measure is run alone "
             "under the same load: %s. A band is judged where the soil resolves it at the "
             "receiver and the reference lies within %g dB of its highest band (`-` elsewhere). "
             "PPV, KB_Fmax and the overall level are those of the record low-passed at the "
             "frequency the mesh resolves at the receiver (%s): what lies above it is the "
             "mesh's, not the ground's." % (info["load"], CONTENT_DB, lowpass_text(
                 info["receivers"], next(iter(losses.values())))), ""]
    for name, per in losses.items():
        m = info["measures"][name]
        lines += ["## %s: %s" % (name, m.kind.replace("_", " ")), "",
                  "%g m from the track, %g m deep, %g m wide, %g m long%s (%d DOFs, the "
                  "reference %d)." % (m.distance, m.depth, m.width, m.length,
                                       "" if m.material is None else
                                       ", c_S %g m/s, rho %g kg/m^3" % (m.material.shear_speed,
                                                                        m.material.density),
                                       info["dofs"][name], info["dofs"]["reference"]), "",
                  "| band (Hz) | " + " | ".join(info["receivers"]) + " |",
                  "|---:|" + "---:|" * len(per)]
        for i, f in enumerate(fc):
            cells = ["-" if math.isnan(il["band"][i]) else "%+.1f" % il["band"][i] for il in per]
            if any(c != "-" for c in cells):
                lines.append("| %.3g | %s |" % (f, " | ".join(cells)))
        for q, label in (("ppv", "PPV"), ("kb_fmax", "KB_Fmax"), ("overall", "overall level")):
            lines.append("| %s | %s |" % (label, " | ".join("%+.1f" % il[q] for il in per)))
        lines += ["", amplifications(info["receivers"], fc, per), ""]
    lines += ["![Insertion loss per band](figures/insertion_loss.png)", ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def figure(path, names, fc, losses):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5))
    styles = ["-", "--", "-.", ":"]
    for j, (name, per) in enumerate(losses.items()):
        for k, (rec, il) in enumerate(zip(names, per)):
            ax.semilogx(fc, il["band"], color="C%d" % (k % 10), ls=styles[j % 4], marker="o",
                        ms=3, label="%s, %s" % (name, rec))
    ax.axhline(0.0, color="k", lw=0.8)
    judged = [f for i, f in enumerate(fc)
              if any(math.isfinite(il["band"][i]) for per in losses.values() for il in per)]
    if judged:  # the judged bands' centres as the ticks, in plain numbers
        ax.set_xticks(judged)
        ax.set_xticklabels(["%.3g" % f for f in judged])
        ax.minorticks_off()
    ax.set_xlabel("one-third-octave band centre (Hz)")
    ax.set_ylabel("insertion loss IL = L_ref - L_measure (dB)")
    ax.text(0.02, 0.03, "above 0: the measure reduces; below 0: it amplifies",
            transform=ax.transAxes, fontsize=9)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def study(scene, out, name="scene", master=None, scene_dir="."):
    """Runs the reference and every measure; writes the outputs into out.
    master: the master program, for a train load (fe_soil/study_load.py);
    scene_dir: the folder of the scene's relative file names."""
    from .model import FESoil

    cfg = fe_config.parse(scene["soil"])
    load = load_keys(scene["soil"].get("mitigation"))
    if not cfg["measures"]:
        raise ConfigError("[soil] measures: the scene lists none ([[soil.measures]]): there is "
                          "nothing to compare with the reference")
    source = study_load.make(
        scene, load, cfg, lambda fps: FESoil(variant_block(cfg, fps, path_measures.REFERENCE)),
        master, os.path.join(out, "train"), scene_dir, keep=True)
    variants = [path_measures.REFERENCE] + [m.name for m in cfg["measures"]]
    records, dofs, bands, start = {}, {}, None, None
    for v in variants:
        print("mitigation: %s" % v, flush=True)
        # What does not change is not done again: the reference runs on the
        # block the train's lumped soil was fitted to, and every variant (the
        # same mesh: fe_soil/config.py) starts its statics from the reference's.
        soil = (source.take_block() if v == path_measures.REFERENCE else None) or FESoil(
            variant_block(cfg, source.footprints, v))
        if start is not None:
            soil.start_statics_from(start)
        t, vel = source.drive(soil)
        records[v], dofs[v] = vel, soil.global_dofs()
        os.makedirs(os.path.join(out, "runs", v), exist_ok=True)
        np.savez(os.path.join(out, "runs", v, "receivers.npz"), t=t, v=vel)
        if bands is None:  # the reference's mesh judges the bands
            bands = resolution.receiver_bands(soil, cfg, load["duration"])
            tops = resolution.resolved_frequencies(soil, cfg)
            start = soil.static_solutions()
        del soil  # one block at a time
    names = [c[: -len("_vz_mps")] for c in fe_config.channel_names(cfg["receivers"])]
    ref = levels(records[path_measures.REFERENCE], source.dt, tops)
    losses = {v: insertion_loss(ref, levels(records[v], source.dt, tops), bands)
              for v in variants[1:]}
    fc = ref[0]["fc"]
    with open(os.path.join(out, "insertion_loss.csv"), "w") as f:
        f.write(csv_text(names, cfg["receivers"], fc, losses))
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    figure(os.path.join(out, "figures", "insertion_loss.png"), names, fc, losses)
    info = {"name": name, "load": source.text(), "receivers": names, "dofs": dofs,
            "measures": {m.name: m for m in cfg["measures"]}}
    report(os.path.join(out, "REPORT.md"), info, fc, losses)
    return records, losses


def default_master():
    """The build's master program beside this package, if there is one."""
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "bin",
                        "master")
    return os.path.normpath(here) if os.path.isfile(here) else None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True, help="a scene with [soil] model = \"fe\" and "
                    "[[soil.measures]]")
    ap.add_argument("--out", required=True, help="the study's folder")
    ap.add_argument("--grounds", action="store_true", help="compare the scene's "
                    "[[soil.grounds]] (embankments, cuttings) with the flat ground instead "
                    "(fe_soil/ground_study.py)")
    ap.add_argument("--master", default=default_master(), help="the master program, for "
                    "[soil.mitigation] load = \"train\" (default: build/bin/master beside "
                    "this package)")
    a = ap.parse_args(argv)
    scene = read_scene(a.scene, "fe")
    if "sleepers" not in scene or "spacing" not in scene["sleepers"]:
        sys.exit("%s: [sleepers] spacing is missing (the footprints' spacing)" % a.scene)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    try:
        if a.grounds:
            from . import ground_study
            ground_study.study(scene, out, scene.get("scene", {}).get("name", a.scene), a.master,
                               os.path.dirname(os.path.abspath(a.scene)))
        else:
            study(scene, out, scene.get("scene", {}).get("name", a.scene), a.master,
                  os.path.dirname(os.path.abspath(a.scene)))
    except ConfigError as e:
        sys.exit("%s: %s" % (a.scene, e))
    print("mitigation: wrote %s" % os.path.join(out, "REPORT.md"), flush=True)


if __name__ == "__main__":
    main()
