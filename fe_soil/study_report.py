"""REPORT.md and the figures of fe_soil.study, from the files of its runs:
every number comes from a run's vibration.csv (the two-step run's is
written by the study in the same format) and every curve from its
receivers.csv, so the report and the files agree."""
import math
import os


ORDER = ["jacobi", "gauss-seidel", "implicit", "two-step"]
TWO_WAY = ["jacobi", "gauss-seidel", "implicit"]
REFERENCE = "implicit"
VALIDATION = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs",
                          "ground-vibration-validation.md")
FE_TESTS = "## Validation (tests/fe_soil"  # the heading of the FE soil's table there


def bands(runs):
    """[(column, centre Hz)] of the vertical band levels finite in every run."""
    row = runs[REFERENCE]["vibration"][0]
    cols = [c for c in row if c.startswith("Lv_z_")]
    keep = [c for c in cols if all(math.isfinite(r[c]) for k in ORDER
                                   for r in runs[k]["vibration"])]
    return [(c, float(c[len("Lv_z_"):-len("Hz_dB")])) for c in keep]


def resolved(row, f):
    """Whether the band centred at f Hz lies in the receiver's resolved
    bands (its vibration.csv row's resolved_from_hz to resolved_to_hz;
    none when they are nan)."""
    lo, hi = row.get("resolved_from_hz", math.nan), row.get("resolved_to_hz", math.nan)
    return lo * (1.0 - 1e-6) <= f <= hi * (1.0 + 1e-6)


def span(row):
    """'1-20 Hz' or 'none': a row's resolved bands (centres)."""
    lo, hi = row.get("resolved_from_hz", math.nan), row.get("resolved_to_hz", math.nan)
    return "%.3g-%.3g Hz" % (lo, hi) if math.isfinite(lo) and math.isfinite(hi) else "none"


def kb_max(r):
    return max(r["kb_fmax_x"], r["kb_fmax_y"], r["kb_fmax_z"])


def load_content(info):
    """The sentence on the load's content above each receiver's resolved
    frequency (the lower of the two estimates)."""
    return ("The load (each footprint's force into the soil, their spectra summed) against the resolved frequency, "
            "per receiver: %s." % "; ".join(v[3] for v in info["load_content"]))


def worst_text(runs, bs, d, only_resolved):
    """'0.95 dB at 4 m, ...': the largest |reference - two-step| per receiver
    over its bands (those resolved there, or all)."""
    out = []
    for k, x in enumerate(d):
        ref, two = runs[REFERENCE]["vibration"][k], runs["two-step"]["vibration"][k]
        diffs = [abs(ref[c] - two[c]) for c, f in bs if not only_resolved or resolved(ref, f)]
        out.append("%.2f dB at %g m" % (max(diffs), x) if diffs else "none resolved at %g m" % x)
    return ", ".join(out)


def answer(runs, info):
    d = info["distances"]
    L = ["## Answer", "",
         "Free field at the receivers (on the surface, beside the middle of the track, at the "
         "given distance from its axis) over %.4g s, sampled every macro step of the soil "
         "(%.3g s). PPV: "
         "the largest component's peak; KB_Fmax: DIN 4150-2's weighted running RMS (largest "
         "component, and vertical); levels: vertical velocity, dB re 1e-9 m/s. Two-way: the "
         "co-simulation with the FE soil at the ss cut (explicit Jacobi, explicit "
         "Gauss-Seidel, implicit); two-step: the forces into the ballast on a lumped soil "
         "fitted to the block's static stiffness (k_f = %.4g N/m, k_c = %.4g N/m), applied "
         "one way to the same block." % (info["t_end"], (info.get("windows") or {}).get(
             "ss", info["H"]), info["kf"], info["kc"]), "",
         "Resolution, per receiver: the largest element on the surface path from the track, "
         "the frequency up to which it has 10 elements per Rayleigh wavelength of the softest "
         "layer (c_R = %.4g m/s: the rule for band levels within about 1 dB, "
         "docs/fe-soil.md, \"The model\") and the 45-degree phase-error estimate: %s. Bands above "
         "are rough, in both methods alike (they share the mesh)." % (
             info["resolution"][0],
             "; ".join("%g m: %.2g m, %.3g Hz (phase %.3g Hz)" % (x, h, f, g) if f > 0.0 else
                       "%g m: in the absorbing layers (damped: nothing resolved)" % x
                       for (h, f, g), x in zip(info["resolution"][1], d))),
         "", load_content(info), "",
         "### Free field per distance", "",
         "| distance | method | PPV (m/s) | PPV_z (m/s) | KB_Fmax | KB_Fmax,z |",
         "|---:|---|---:|---:|---:|---:|"]
    for k, dist in enumerate(d):
        for m in ORDER:
            r = runs[m]["vibration"][k]
            L.append("| %g m | %s | %.4e | %.4e | %.4g | %.4g |" % (
                dist, runs[m]["label"], r["ppv_mps"], r["ppv_z_mps"], kb_max(r), r["kb_fmax_z"]))
    L += damped(info)
    bs = bands(runs)
    if not bs:
        L += ["", "No one-third-octave band of 1-100 Hz holds a spectral line of a %.4g s "
              "record." % info["t_end"]]
    else:
        L += ["", "### One-third-octave levels of v_z (dB re 1e-9 m/s), %s co-simulation"
              % runs[REFERENCE]["label"], "",
              "Bands with no spectral line in the %.4g s record are left out." % info["t_end"],
              "", "| band (Hz) | " + " | ".join("%g m" % x for x in d) + " |",
              "|---:|" + "---:|" * len(d)]
        ref = runs[REFERENCE]["vibration"]
        for c, f in bs:
            L.append("| %.3g | %s |" % (f, " | ".join(
                "%.2f" % ref[k][c] for k in range(len(d)))))
        L += ["", "Resolved at each receiver (its vibration.csv's resolved_from_hz to "
              "resolved_to_hz, band centres): %s. The other levels are the mesh's: rough, "
              "in both methods alike." % "; ".join(
                  "%g m: %s" % (x, span(ref[k])) for k, x in enumerate(d))]
        L += ["", "### Two-way minus two-step (dB)", "",
              "Per distance and band: the two-step level, each two-way level minus it, and "
              "whether the mesh resolves the band there."]
        for k, dist in enumerate(d):
            L += ["", "#### %g m" % dist, "",
                  "| band (Hz) | two-step (dB) | " + " | ".join(
                      "%s - two-step" % runs[m]["label"] for m in TWO_WAY) + " | resolved |",
                  "|---:|---:|" + "---:|" * len(TWO_WAY) + "---|"]
            for c, f in bs:
                base = runs["two-step"]["vibration"][k][c]
                L.append("| %.3g | %.2f | %s | %s |" % (f, base, " | ".join(
                    "%+.2f" % (runs[m]["vibration"][k][c] - base) for m in TWO_WAY),
                    "yes" if resolved(ref[k], f) else "no"))
        L += ["", "Largest |%s - two-step| over the bands resolved: %s; over every band: %s." % (
            runs[REFERENCE]["label"], worst_text(runs, bs, d, True),
            worst_text(runs, bs, d, False))]
    L += ["", "### Cost", "",
          "Wall time of each method on this machine (load average: the 1-minute load when "
          "it started). A co-simulation's time is the whole `master run` (it starts the nodes "
          "and the FE soil, finds the static state, steps, writes).", "",
          "| method | what runs | wall (s) | load | iterations per macro step |",
          "|---|---|---:|---:|---|"]
    for m in TWO_WAY:
        r = runs[m]
        it = r["summary"].get("iterations")
        its = "%s mean, %s max" % (it["mean"], it["max"]) if it else "1"
        L.append("| %s | `master run --case %s%s` | %.1f | %.2f | %s |" % (
            r["label"], r["case"], "".join(" " + x for x in r["extra"]), r["wall"], r["load"], its))
    c = runs["two-step"]["cost"]
    L.append("| two-step | the FE block built and fitted (2 static solves) %.1f s; lumped soil, "
             "monolithic %.1f s; the FE block one way %.1f s | %.1f | %.2f | 1 (no coupling) |" % (
                 c["fit"], c["lumped"], c["one_way"], runs["two-step"]["wall"], c["load"][0]))
    if info["ranks"] > 1:
        L += ["", "The co-simulations ran the FE soil on %d MPI ranks ([soil] ranks); the "
              "two-step method's one-way run ran on one, in the study's process, so its time "
              "is not comparable with theirs as it stands." % info["ranks"]]
    L += ["", "The whole study took %.1f s (load average %.2f at its end); the FE block has %d "
          "degrees of freedom." % (info["total"], info["load"], info["dofs"])]
    return L


def decay(runs, info):
    d = info["distances"]
    L = ["## Decay with distance", "",
         "PPV_z and KB_Fmax,z against distance, %s co-simulation and two-step; n is the local "
         "exponent of a power law r^-n between a receiver and the one before it, "
         "n = -ln(a2/a1) / ln(r2/r1)." % runs[REFERENCE]["label"], "",
         "| distance | PPV_z (m/s) | / nearest | n | KB_Fmax,z | n | two-step PPV_z | n |",
         "|---:|---:|---:|---:|---:|---:|---:|---:|"]

    def n(vals, k):
        if k == 0 or vals[k] <= 0 or vals[k - 1] <= 0:
            return "-"
        return "%.2f" % (-math.log(vals[k] / vals[k - 1]) / math.log(d[k] / d[k - 1]))

    ref, two = runs[REFERENCE]["vibration"], runs["two-step"]["vibration"]
    p = [r["ppv_z_mps"] for r in ref]
    kb = [r["kb_fmax_z"] for r in ref]
    p2 = [r["ppv_z_mps"] for r in two]
    for k, dist in enumerate(d):
        L.append("| %g m | %.4e | %.3f | %s | %.4g | %s | %.4e | %s |" % (
            dist, p[k], p[k] / p[0], n(p, k), kb[k], n(kb, k), p2[k], n(p2, k)))
    return L + damped(info)


def damped(info):
    """The sentence naming the receivers inside the absorbing layers (no
    resolved frequency: info["resolution"]), whose measures are the
    layers' damping, not the ground's; nothing when there are none."""
    inside = ["%g m" % x for (_, f, _), x in zip(info["resolution"][1], info["distances"])
              if f <= 0.0]
    if not inside:
        return []
    return ["", "%s: inside the absorbing layers, which damp %s: %s PPV, KB_Fmax, levels "
            "and decay exponent are the layers', not the ground's (raise [soil] resolve_to "
            "beyond %s to measure there)." % (
                ", ".join(inside), "them" if len(inside) > 1 else "it",
                "their" if len(inside) > 1 else "its", "them" if len(inside) > 1 else "it")]


def validation(info):
    L = ["## Validation", "", "### Checks run by this study", "",
         "| check | bound | measured | result |", "|---|---|---|---|"]
    for what, bound, measured, ok in info["checks"]:
        L.append("| %s | %s | %s | %s |" % (what, bound, measured,
                                             "not run" if ok is None else
                                             ("pass" if ok else "**FAIL**")))
    return L + ["", "### The FE soil's tests", ""] + tests_table(FE_TESTS, "fe_soil")


def tests_table(heading, label):
    """The validation table under `heading` in docs/ground-vibration-validation.md
    (its rows, to the next heading), said to be the tests' and not run by
    the study; where to look when the file is not beside the package or
    has no such table. label: the tests' folder and ctest label."""
    try:
        with open(VALIDATION) as f:
            text = f.read()
        start = text.index(heading)
        end = text.find("\n#", start + 1)
        rows = [x for x in text[start:end if end > 0 else None].splitlines()
                if x.startswith("|")]
    except (OSError, ValueError):
        rows = []
    if not rows:
        return ["docs/ground-vibration-validation.md (its section \"%s\") is not beside this "
                "package: run `ctest -L %s`." % (heading.lstrip("# "), label)]
    return ["Not run by this study: the validation table of "
            "docs/ground-vibration-validation.md, whose measured values the tests in "
            "tests/%s (`ctest -L %s`) check against the bounds." % (label, label), ""] + rows


def windows_line(info):
    """Which windows the co-simulations ran (the scene's [coupling] CUT_macro_step)."""
    w = info.get("windows") or {}
    if not w:
        return ("Windows: every cut at the macro step H = %.3g s (single rate); the receivers "
                "are sampled every H." % info["H"])
    cuts = ", ".join("%s at %.3g s (%d H)" % (c, x, round(x / info["H"])) for c, x in sorted(w.items()))
    return ("Windows: H = %.3g s; in the co-simulations %s (the scene's [coupling]: multirate, "
            "docs/coupling.md), the other cuts at H. The FE soil steps at the ss window and its "
            "receivers are sampled at it; the two-step method runs at H." % (info["H"], cuts))


def write(out, runs, info):
    from . import study_figures

    figs = study_figures.draw(out, runs, info, [m for m in ORDER])
    L = ["# Ground-vibration study: %s" % info["name"], "",
         "Scene `%s`. Written by `python3 -m fe_soil.study`." % os.path.basename(info["scene"]),
         "", windows_line(info), ""]
    L += answer(runs, info) + [""] + decay(runs, info) + ["", "## Figures", ""]
    L += ["- `figures/%s`: %s" % (name, what) for name, what in figs]
    L += [""] + validation(info)
    L += ["", "## Files", "",
          "- `runs/<method>/<case>/`: each co-simulation's files (`vibration.csv`: the measures "
          "per receiver; `receivers.csv`: the velocity series; `history.csv`, `summary.json`)",
          "- `runs/two-step/`: the one-way run's `vibration.csv` and `receivers.csv`, "
          "`velocity.xdmf` + `velocity.h5` (the velocity field at the snapshot times; ParaView "
          "opens it) and `surface.npz`; `runs/lumped/monolithic/`: step 1 and its "
          "`soil_forces.csv`; `lumped.toml`: its scene", ""]
    with open(os.path.join(out, "REPORT.md"), "w") as f:
        f.write("\n".join(L))
