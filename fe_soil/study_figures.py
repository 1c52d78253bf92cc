"""The figures of fe_soil.study (matplotlib, Agg): levels against distance,
spectra and velocity series per receiver, surface velocity snapshots."""
import math
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402,F401

STYLE = {"jacobi": ("C0", "o", "-"), "gauss-seidel": ("C1", "s", "--"),
         "implicit": ("C2", "^", "-."), "two-step": ("C3", "x", ":")}


def receivers(folder):
    """(t, vz[time, receiver]) from a run's receivers.csv."""
    data = np.loadtxt(os.path.join(folder, "receivers.csv"), delimiter=",", skiprows=1, ndmin=2)
    return data[:, 0], data[:, 3::3]


def levels_vs_distance(path, runs, info, order):
    d = info["distances"]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for m in order:
        c, mk, ls = STYLE[m]
        vib = runs[m]["vibration"]
        ax[0].loglog(d, [r["ppv_z_mps"] for r in vib], color=c, marker=mk, ls=ls,
                     label=runs[m]["label"])
        ax[1].loglog(d, [r["kb_fmax_z"] for r in vib], color=c, marker=mk, ls=ls,
                     label=runs[m]["label"])
    ax[0].set_ylabel("PPV of v_z (m/s)")
    ax[1].set_ylabel("KB_Fmax,z")
    # Band levels against distance: up to six bands held by every run,
    # the implicit run solid, the two-step run dotted.
    cols = [c for c in runs["implicit"]["vibration"][0] if c.startswith("Lv_z_")]
    cols = [c for c in cols if all(math.isfinite(r[c]) for m in order
                                   for r in runs[m]["vibration"])]
    pick = [cols[int(round(i))] for i in np.linspace(0, len(cols) - 1, min(6, len(cols)))] \
        if cols else []
    for j, col in enumerate(dict.fromkeys(pick)):
        f = float(col[len("Lv_z_"):-len("Hz_dB")])
        ax[2].semilogx(d, [r[col] for r in runs["implicit"]["vibration"]], color="C%d" % j,
                       marker="^", label="%.3g Hz" % f)
        ax[2].semilogx(d, [r[col] for r in runs["two-step"]["vibration"]], color="C%d" % j,
                       marker="x", ls=":")
    ax[2].set_ylabel("L_v of v_z (dB re 1e-9 m/s)")
    ax[2].set_title("bands: implicit (solid), two-step (dotted)", fontsize=9)
    for a in ax:
        a.set_xlabel("distance from the track axis (m)")
        a.set_xticks(d)
        a.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        a.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def spectra(path, runs, info, order):
    d = info["distances"]
    fig, axes = plt.subplots(1, len(d), figsize=(4 * len(d), 3.6), sharey=True, squeeze=False)
    for k, (a, dist) in enumerate(zip(axes[0], d)):
        for m in order:
            c, mk, ls = STYLE[m]
            row = runs[m]["vibration"][k]
            cols = [x for x in row if x.startswith("Lv_z_")]
            f = np.array([float(x[len("Lv_z_"):-len("Hz_dB")]) for x in cols])
            lv = np.array([row[x] for x in cols])
            ok = np.isfinite(lv)
            a.semilogx(f[ok], lv[ok], color=c, marker=mk, ls=ls, label=runs[m]["label"])
        a.set_title("%g m" % dist)
        a.set_xlabel("one-third-octave band (Hz)")
        a.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("L_v of v_z (dB re 1e-9 m/s)")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def velocity(path, runs, info, order):
    d = info["distances"]
    fig, axes = plt.subplots(len(d), 1, figsize=(8, 2.4 * len(d)), sharex=True, squeeze=False)
    for m in order:
        c, _, ls = STYLE[m]
        folder = runs[m]["folder"]
        t, vz = receivers(folder)
        for k, a in enumerate(axes[:, 0]):
            a.plot(t, vz[:, k] * 1e3, color=c, ls=ls, lw=1.0, label=runs[m]["label"])
    for k, a in enumerate(axes[:, 0]):
        a.set_ylabel("v_z at %g m (mm/s)" % d[k])
        a.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("t (s)")
    axes[0, 0].legend(fontsize=8, ncol=4)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def snapshots(path, npz):
    s = np.load(npz)
    n = len(s["t"])
    cols = min(3, n)
    rows = math.ceil(n / cols)
    aspect = float(np.ptp(s["y"]) / max(np.ptp(s["x"]), 1e-9))
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols + 1, (5 * aspect + 0.9) * rows),
                             squeeze=False, layout="constrained")
    lim = float(np.abs(s["vz"]).max()) * 1e3 or 1.0
    for j, a in enumerate(axes.flat):
        if j >= n:
            a.axis("off")
            continue
        im = a.tripcolor(s["x"], s["y"], s["vz"][j] * 1e3, shading="gouraud", cmap="RdBu_r",
                         vmin=-lim, vmax=lim)
        r = s["receivers"]
        a.plot(r[:, 0], r[:, 1], "k^", ms=4)
        a.set_title("t = %.4g s" % s["t"][j], fontsize=9)
        a.set_aspect("equal")
        a.set_xlabel("x along the block (m)", fontsize=8)
        a.set_ylabel("y (m)", fontsize=8)
    fig.colorbar(im, ax=axes.ravel().tolist(), label="v_z, positive up (mm/s)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def draw(out, runs, info, order):
    """Draws every figure into out/figures; [(file name, one line on it)]."""
    folder = os.path.join(out, "figures")
    os.makedirs(folder, exist_ok=True)
    figs = [("levels_vs_distance.png",
             "PPV and KB_Fmax of v_z against distance, each method (log-log), and up to six "
             "one-third-octave levels against distance (implicit and two-step)",
             lambda p: levels_vs_distance(p, runs, info, order)),
            ("spectra.png", "one-third-octave levels of v_z per receiver, each method",
             lambda p: spectra(p, runs, info, order)),
            ("velocity.png", "v_z(t) per receiver, each method",
             lambda p: velocity(p, runs, info, order)),
            ("surface_snapshots.png",
             "vertical velocity on the surface of the half block (y >= 0, the track along y = 0; "
             "triangles: the receivers) at the snapshot times of the two-step run",
             lambda p: snapshots(p, os.path.join(runs["two-step"]["folder"], "surface.npz")))]
    for name, _, fn in figs:
        fn(os.path.join(folder, name))
    return [(name, what) for name, what, _ in figs]
