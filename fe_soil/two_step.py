"""The two-step method beside the two-way co-simulation.

    /usr/bin/python3 -m fe_soil.two_step --scene FE_SCENE --master BIN/master --out DIR

Two-way: `master run --case ss-xt-jacobi` on a scene whose soil is the FE
soil (model = "fe"): vehicle, track and soil exchange every macro step.
Two-step: (1) the same vehicle and track on a lumped soil fitted to the FE
block's static stiffness (`fit_lumped`), run monolithically, give the
forces into the ballast under every sleeper (soil_forces.csv); (2) those
forces are applied one way to the same FE block, which never feeds back.
Both runs' receivers then give PPV, KB_Fmax and vertical one-third-octave
levels per distance; DIR/two_step.md is the comparison (a report section)
and DIR/two_step.csv its numbers.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import tomllib

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sdk",
                                "python"))
from railcosim_sdk import Footprint  # noqa: E402

from . import config as fe_config  # noqa: E402
from . import measures  # noqa: E402

CASE = "ss-xt-jacobi"


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


def fit_lumped(soil, n):
    """(k_f, k_c): a lumped soil (a spring k_f per sleeper to the ground, k_c
    between neighbours) with the FE block's static stiffness when every
    footprint carries the same force (the coupling springs then carry
    nothing: k_f = F / u at the middle footprint) and when the middle one
    alone does (an endless chain's stiffness there is k_f + 2 k_c (1 - r),
    r + 1/r = 2 + k_f/k_c; k_c by bisection). Leaves the soil at rest."""
    kf = 1e5 / soil.statics(np.full(n, 1e5))[n // 2]
    one = np.zeros(n)
    one[n // 2] = 1e5
    kp = 1e5 / soil.statics(one)[n // 2]
    soil.reset()

    def point(kc):
        b = 2.0 + kf / kc
        return kf + 2.0 * kc * (1.0 - (b - math.sqrt(b * b - 4.0)) / 2.0)

    lo, hi = 1e-3 * kf, 1e6 * kf
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if point(mid) < kp else (lo, mid)
    return kf, mid


def footprints(scene, xs):
    """A footprint under one rail's half of each sleeper at xs (m), as the ss
    cut sends them."""
    spacing = scene["sleepers"]["spacing"]
    length = scene["sleepers"].get("length", 2.6)
    return [Footprint(x, length / 4.0, 0.0, spacing, length / 2.0) for x in xs]


def block(scene, xs):
    """The FE soil of the scene's [soil] table under footprints at xs (m)."""
    from .model import FESoil

    fps = footprints(scene, xs)
    cfg = fe_config.parse(scene["soil"])
    params, _ = fe_config.block_params(cfg, fps)
    return FESoil(params), cfg


def lumped_table(cfg, kf, kc, spacing, length):
    """The [soil] table of the fitted lumped soil. Stiffnesses fitted; the
    mass and the damping to the ground from the top layer by the
    conventions of scenes/soil.toml (Lysmer's analog: c_f = 3.4 r^2
    sqrt(rho G) / (1 - nu); the block under the footprint to a depth r,
    m_f = rho A r; r = sqrt(A / pi), A the footprint)."""
    top = cfg["layers"][0]
    area = spacing * length / 2.0
    r = math.sqrt(area / math.pi)
    cf = 3.4 * r * r * math.sqrt(top.density * top.shear_modulus) / (1.0 - top.poisson)
    return ("[soil]\nmodel = \"lumped\"\nstiffness = %.9e\ndamping = %.9e\nmass = %.9e\n"
            "coupling_stiffness = %.9e\ncoupling_damping = 0.0\n\n"
            % (kf, cf, top.density * area * r, kc))


def run_master(master, scene, out, case):
    p = subprocess.run([master, "run", "--scene", scene, "--case", case, "--out", out],
                       capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("master run --scene %s --case %s failed:\n%s" % (scene, case, p.stdout + p.stderr))
    return os.path.join(out, case)


def one_way(soil, forces, t, H, hold=False, after_step=None):
    """The FE soil under the recorded forces: statics at the first row, then
    one macro step per row with the forces linear in between (hold: each
    row's force held over its step, as a Jacobi co-simulation with held
    inputs delivers it). after_step(k, soil), if given, is called after
    step k (1 .. rows - 1)."""
    soil.reset()
    soil.statics(forces[0])
    for k in range(len(t) - 1):
        soil.advance(t[k], H, forces[k], forces[k] if hold else forces[k + 1])
        if after_step is not None:
            after_step(k + 1, soil)
    return soil.receiver_series()


def write_scene(scene, scene_dir, soil, path, note, end_time=None):
    """Writes to path the scene on the given [soil] table, with ballast
    forces written (soil_forces.csv) and, if given, another end time; a
    relative rail profile file is named from scene_dir, the scene's own
    folder. Raises scene_file.SceneWriteError on a value TOML cannot hold."""
    from .scene_file import toml_text

    s = {k: v for k, v in scene.items() if k not in ("soil", "output")}
    if end_time is not None:
        s["simulation"] = dict(scene.get("simulation", {}), end_time=end_time)
    irr = s.get("irregularity", {})
    if isinstance(irr.get("file"), str) and not os.path.isabs(irr["file"]):
        s["irregularity"] = dict(irr, file=os.path.join(os.path.abspath(scene_dir), irr["file"]))
    s["soil"] = soil
    s["output"] = {"ballast_forces": True}
    text = toml_text(s)
    with open(path, "w") as f:
        f.write("".join("# %s\n" % line for line in note.splitlines()) + text + "\n")
    return path


def lumped_scene(scene_path, scene, cfg, kf, kc, path):
    """Writes to path the scene with the FE soil replaced by the fitted
    lumped one (write_scene)."""
    spacing, length = scene["sleepers"]["spacing"], scene["sleepers"].get("length", 2.6)
    soil = tomllib.loads(lumped_table(cfg, kf, kc, spacing, length))["soil"]
    return write_scene(scene, os.path.dirname(os.path.abspath(scene_path)), soil, path,
                       "%s on the lumped soil fitted to its FE block (fe_soil/two_step.py)"
                       % scene_path)


def summaries(v, dt):
    return [measures.receiver_summary(v[:, k, :], dt) for k in range(v.shape[1])]


def compare(two_way, two_step, distances, dt, duration):
    """The report section (markdown) and the rows of two_step.csv."""
    rows = [["distance_m", "measure", "two_way", "two_step", "difference"]]
    lines = ["## Two-step method against the two-way co-simulation", "",
             "Vertical velocity of each receiver over %.3g s, sampled every %.3g s. Levels in dB "
             "re 1e-9 m/s; difference = two-step minus two-way (dB, or relative for PPV and "
             "KB_Fmax). Bands with no spectral line in the record are left out." % (duration, dt),
             "", "| distance | PPV two-way (m/s) | two-step | diff. | KB_Fmax,z two-way | two-step "
             "| diff. |", "|---:|---:|---:|---:|---:|---:|---:|"]
    for d, a, b in zip(distances, two_way, two_step):
        pa, pb = a["ppv_components"][2], b["ppv_components"][2]
        ka, kb = a["kb_fmax"][2], b["kb_fmax"][2]
        lines.append("| %g m | %.3e | %.3e | %+.1f %% | %.3g | %.3g | %+.1f %% |"
                     % (d, pa, pb, 100 * (pb / pa - 1), ka, kb, 100 * (kb / ka - 1)))
        rows += [[d, "ppv_z_mps", pa, pb, pb / pa - 1], [d, "kb_fmax_z", ka, kb, kb / ka - 1]]
    centres = two_way[0]["band_centres"]
    keep = [i for i, _ in enumerate(centres)
            if all(math.isfinite(s["band_levels"][2][i]) for s in two_way + two_step)]
    if keep:
        lines += ["", "One-third-octave levels of v_z, two-way / two-step (difference):", "",
                  "| band (Hz) | " + " | ".join("%g m" % d for d in distances) + " |",
                  "|---:|" + "---:|" * len(distances)]
        for i in keep:
            cells = []
            for d, a, b in zip(distances, two_way, two_step):
                la, lb = a["band_levels"][2][i], b["band_levels"][2][i]
                cells.append("%.1f / %.1f (%+.1f)" % (la, lb, lb - la))
                rows.append([d, "Lv_z_%gHz_dB" % centres[i], la, lb, lb - la])
            lines.append("| %.3g | %s |" % (centres[i], " | ".join(cells)))
    return "\n".join(lines) + "\n", rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True, help="a scene with [soil] model = \"fe\"")
    ap.add_argument("--master", required=True, help="the master program")
    ap.add_argument("--out", required=True)
    a = ap.parse_args(argv)
    with open(a.scene, "rb") as f:
        scene = tomllib.load(f)
    if scene.get("soil", {}).get("model") != "fe":
        sys.exit("%s: [soil] model must be \"fe\"" % a.scene)
    os.makedirs(a.out, exist_ok=True)
    # Two-way.
    two = run_master(a.master, a.scene, os.path.join(a.out, "two-way"), CASE)
    _, soil_csv = read_csv(os.path.join(two, "soil.csv"))
    _, rec = read_csv(os.path.join(two, "receivers.csv"))
    # Step 1: the fitted lumped soil, monolithic, its ballast forces.
    soil, cfg = block(scene, soil_csv[:, 0])
    kf, kc = fit_lumped(soil, len(soil_csv))
    lumped = lumped_scene(a.scene, scene, cfg, kf, kc, os.path.join(a.out, "lumped.toml"))
    mono = run_master(a.master, lumped, os.path.join(a.out, "lumped"), "monolithic")
    head, forces = read_csv(os.path.join(mono, "soil_forces.csv"))
    t, H = forces[:, 0], float(forces[1, 0] - forces[0, 0])
    # Step 2: those forces one way into the FE soil.
    _, v = one_way(soil, forces[:, 1:], t, H)
    flat = np.column_stack([t[1:], v.reshape(len(t) - 1, -1)])
    np.savetxt(os.path.join(a.out, "two_step_receivers.csv"), flat, delimiter=",",
               header="t_s," + ",".join("r%d_%s_mps" % (k, c) for k in range(v.shape[1])
                                        for c in ("vx", "vy", "vz")), comments="", fmt="%.9g")
    v_two = rec[:, 1:].reshape(len(rec), -1, 3)
    section, rows = compare(summaries(v_two, H), summaries(v, H), cfg["receivers"], H, t[-1])
    two_forces = os.path.join(two, "soil_forces.csv")
    if os.path.exists(two_forces):  # what the FE soil received in the two-way run
        _, f_two = read_csv(two_forces)
        diff = np.abs(f_two[:, 1:] - forces[:, 1:]).max() / np.abs(f_two[:, 1:]).max()
        section += ("\nThe ballast forces of step 1 differ from those the FE soil received in "
                    "the two-way run by at most %.2g of their peak.\n" % diff)
    section += ("\nThe lumped soil of step 1: k_f = %.4g N/m, k_c = %.4g N/m fitted to the FE "
                "block's static stiffness; mass and damping by scenes/soil.toml's conventions "
                "(%s).\n" % (kf, kc, lumped))
    with open(os.path.join(a.out, "two_step.md"), "w") as f:
        f.write(section)
    with open(os.path.join(a.out, "two_step.csv"), "w", newline="") as f:
        csv.writer(f).writerows(rows)
    print(section)


if __name__ == "__main__":
    main()
