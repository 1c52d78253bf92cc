"""The layered ground on both soils: the Green's-function soil against the
FE soil where the FE soil is valid. The ground-vibration scene's layers
and damping band (scenes/ground_vibration.toml), one sleeper's footprint
(the scene's spacing along the track, 2.6 m across, centred on the axis)
loaded by the same vertical force, a Gaussian pulse (flat from 0 Hz, under
1 % of its energy above the frequency the FE mesh resolves, so that the
low bands get their share of it), the vertical surface velocity at
4, 8 and 16 m over the whole record: PPV and the one-third-octave levels of
every band that holds a spectral line, up to the frequency the FE mesh
resolves at the receiver, within 1.5 dB (issue 39), two independent
methods on the same ground.

The same material on both sides: the FE soil damps each layer the Rayleigh
way (its damping ratio matched at the scene's damping band, 5 and 50 Hz),
and the Green's functions are computed here with that law
(green_soil.spectral.RayleighLayer: a complex density and complex moduli,
the FE soil's equation of motion exactly), not with the Green's-function
soil's own hysteretic law; what the two laws differ by is measured apart
(`--measure`, docs/ground-vibration-validation.md).

The CI size: the FE soil's mesh-size rule at F_MESH = 10.5 Hz (h = 1.14 m,
10 elements per Rayleigh wavelength of the top layer) in x and y out to
18 m from the footprint, each layer its own rule in z, the elements
growing by 1.25 beyond that out to 150 m (the block's boundary, springs and
dashpots, is then far enough for the 1 to 2 Hz bands: at 60 m it was
1.5 to 2 dB off there), a 2 s record (its lines 0.5 Hz apart). The mesh
resolves 10.5 Hz, not the 20 Hz of the scene's own mesh: the issue's full
size (20 Hz to 16 m) is a measurement, `--measure` with F_MESH 20, whose
numbers are in docs/ground-vibration-validation.md.

    /usr/bin/python3 tests/green_soil/test_fe_layered.py            # the test
    nice -n 10 /usr/bin/python3 tests/green_soil/test_fe_layered.py --measure \\
        [--f-mesh 20] [--elastic] [--fine 18]   # the comparison's numbers, both damping laws
"""
import argparse
import math
import os
import sys
import time
import tomllib
import unittest

import numpy as np

import support  # noqa: F401  (skips without scipy; the checkout on the path)

try:
    import dolfinx  # noqa: F401
except ImportError as e:  # pragma: no cover
    print(f"SKIP: dolfinx is not importable ({e}); "
          "scripts/install-deps.sh --fe installs python3-dolfinx")
    sys.exit(77)

from fe_soil import config as fe_config, measures, spectrum  # noqa: E402
from fe_soil.params import Footprint, Layer, SoilParams, graded_nodes, rayleigh_speed  # noqa: E402
from fe_soil.resolution import resolution  # noqa: E402
from green_soil import responses as R, spectral  # noqa: E402

SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "scenes", "ground_vibration.toml")
DISTANCES = (4.0, 8.0, 16.0)
BOUND_DB = 1.5  # issue 39: band levels of the two methods
F_MESH = 10.5  # Hz: the CI mesh's rule (the scene's own: 20)
FINE = 18.0  # m: the rule's h in x and y out to here from the footprint
REACH = 150.0  # m: the block's half length, half width and depth
GROWTH = 1.25
H = 1e-3  # s: the load's and the records' step
RECORD = 2.0  # s
PULSE_T0 = 0.2  # s: the pulse's centre
AMPLITUDE = 1e5  # N
ACROSS = 2.6  # m: the sleeper's length (the FE soil's default)


def scene_ground():
    """(layers, damping law (f1, f2, cutoff), footprint along the track) of
    the scene."""
    with open(SCENE, "rb") as f:
        scene = tomllib.load(f)
    soil = scene["soil"]
    cfg = fe_config.parse({"layers": soil["layers"], "damping_band": soil["damping_band"],
                           "receivers": list(DISTANCES)})
    law = (*cfg["damping_band"], cfg["damping_cutoff"])
    return cfg["layers"], law, float(scene["sleepers"]["spacing"])


def pulse(t, f_mesh=F_MESH):
    """The force: A exp(-((t - t0)/tau)^2), tau = 0.44 / f_mesh; its
    energy above f_mesh is erfc(sqrt(2) pi f_mesh tau) = 0.0057."""
    tau = 0.44 / f_mesh
    return AMPLITUDE * np.exp(-(((np.asarray(t, dtype=float) - PULSE_T0) / tau) ** 2))


def fe_params(layers, band, along, f_mesh, fine=FINE):
    """The FE block: the footprint at its centre on the symmetry plane."""
    h = min(rayleigh_speed(l.shear_speed, l.poisson) for l in layers) / (10.0 * f_mesh)
    return SoilParams(
        length=2.0 * REACH, half_width=REACH, depth=REACH, layers=layers,
        footprints=[Footprint(REACH, along, ACROSS, 0.0)],
        receivers=[(REACH, d) for d in DISTANCES], f_max=f_mesh, damping_band=tuple(band[:2]),
        damping_cutoff=band[2],
        x_nodes=graded_nodes(0.0, 2.0 * REACH, REACH, h, fine, GROWTH),
        y_nodes=graded_nodes(0.0, REACH, 0.0, h, fine, GROWTH),
        z_nodes=fe_config.graded_layer_nodes(layers, REACH, f_mesh, 10.0, GROWTH))


def fe_run(layers, band, along, f_mesh, fine=FINE):
    """(v_z downward (n, receivers), resolved Hz per receiver, DOFs, seconds)."""
    from fe_soil.model import FESoil

    start = time.time()
    soil = FESoil(fe_params(layers, band, along, f_mesh, fine))
    n = int(round(RECORD / H))
    for k in range(n):
        soil.advance(k * H, H, [float(pulse(k * H, f_mesh))], [float(pulse((k + 1) * H, f_mesh))])
    _, v = soil.receiver_series()
    _, per = resolution(soil, {"layers": layers, "receivers": list(DISTANCES)})
    # The FE soil's z points up; the Green's functions' displacement, as the
    # force, points down.
    return -v[:, :, 2], [f for _, f, _ in per], soil.global_dofs(), time.time() - start


def green_run(layers, along, f_mesh=F_MESH):
    """v_z downward (n, receivers) at t = H, 2 H, ..., RECORD."""
    rec = R.Record(dt=H, duration=RECORD, f_max=4.0 * f_mesh)  # the pulse: 5e-14 there
    _, w = rec.frequencies()
    _, points = R.spectra(layers, R.Footprint(along, ACROSS), [], [(0.0, d) for d in DISTANCES],
                          w)
    force = R.damped_spectrum(pulse(np.arange(rec.n_fft) * H, f_mesh), rec)
    _, v = R.to_time(points * (1j * w)[None, :], rec, force)
    return v[:, 1:].T


def differences(fe, green, resolved):
    """Per receiver: (PPV difference dB, {band centre: level difference dB}
    over the bands with a line up to the resolved frequency, the
    correlation of the two waveforms at zero lag)."""
    out = []
    for i, f_res in enumerate(resolved):
        a, b = fe[:, i], green[:, i]
        centres, la = measures.third_octave_levels(a, H)
        _, lb = measures.third_octave_levels(b, H)
        keep = np.isfinite(lb) & (centres <= f_res)
        bands = {float(c): float(x - y) for c, x, y in zip(centres[keep], la[keep], lb[keep])}
        ppv = 20.0 * math.log10(measures.ppv(a) / measures.ppv(b))
        out.append((ppv, bands, float(a @ b / math.sqrt((a @ a) * (b @ b)))))
    return out


def worst(diffs):
    return max(max(abs(p), *(abs(x) for x in b.values())) for p, b, _ in diffs)


class FELayered(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.layers, cls.band, cls.along = scene_ground()
        cls.fe, cls.resolved, cls.dofs, cls.seconds = fe_run(cls.layers, cls.band, cls.along,
                                                             F_MESH)
        cls.green = green_run(spectral.rayleigh_layers(cls.layers, cls.band[:2], cls.band[2]), cls.along)
        cls.diffs = differences(cls.fe, cls.green, cls.resolved)

    def test_resolution_and_load(self):
        # The FE soil's own account of its mesh: 10 elements per Rayleigh
        # wavelength of the top layer at F_MESH on every path; the load's
        # energy above it under the FE soil's 1 % (fe_soil/spectrum.py).
        for f in self.resolved:
            self.assertAlmostEqual(f, F_MESH, delta=1e-9)
        share = spectrum.energy_above(pulse(np.arange(int(RECORD / H)) * H), H, F_MESH)
        self.assertLess(share, spectrum.ABOVE_SHARE)
        self.assertLess(self.dofs, 100_000)

    def test_band_levels_within_the_bound(self):
        for d, (_, bands, _) in zip(DISTANCES, self.diffs):
            # 1, 1.6, 2, 2.5, ..., 10 Hz: the 1.25 Hz band holds no line of a 2 s record.
            self.assertEqual(len(bands), 10, (d, sorted(bands)))
            bad = {f: round(x, 2) for f, x in bands.items() if abs(x) > BOUND_DB}
            self.assertFalse(bad, "%g m: bands over %g dB: %s" % (d, BOUND_DB, bad))

    def test_ppv_within_the_bound(self):
        for d, (ppv, _, _) in zip(DISTANCES, self.diffs):
            self.assertLess(abs(ppv), BOUND_DB, "%g m: PPV %+.2f dB" % (d, ppv))

    def test_waveforms_agree(self):
        # Beyond the measures: the same waveform, the same sign (a
        # polarity or a delay would show here, not in levels or PPV).
        for d, (_, _, corr) in zip(DISTANCES, self.diffs):
            self.assertGreater(corr, 0.95, "%g m" % d)

    def test_a_layer_ten_percent_off_is_seen(self):
        # The comparison's power: the second layer's c_S 10 % higher on the
        # Green's side only.
        layers = [Layer(l.thickness, l.density, l.shear_speed * (1.1 if k == 1 else 1.0),
                        l.poisson, l.damping) for k, l in enumerate(self.layers)]
        off = green_run(spectral.rayleigh_layers(layers, self.band[:2], self.band[2]), self.along)
        self.assertGreater(worst(differences(self.fe, off, self.resolved)), BOUND_DB)


def report(title, diffs, resolved):
    print("\n%s" % title)
    for d, f_res, (ppv, bands, corr) in zip(DISTANCES, resolved, diffs):
        print("%5g m (resolved %.3g Hz): PPV %+.2f dB, correlation %.4f, largest band %.2f dB"
              % (d, f_res, ppv, corr, max(abs(x) for x in bands.values())))
        print("        " + " ".join("%.3g:%+.2f" % kv for kv in sorted(bands.items())))


def measure(argv):
    ap = argparse.ArgumentParser(description="the comparison's numbers, both damping laws")
    ap.add_argument("--measure", action="store_true")
    ap.add_argument("--f-mesh", type=float, default=F_MESH, help="the FE mesh's rule, Hz")
    ap.add_argument("--elastic", action="store_true", help="both soils without damping")
    ap.add_argument("--fine", type=float, default=FINE,
                    help="m: the rule's h in x and y out to here (default %g)" % FINE)
    a = ap.parse_args(argv)
    layers, band, along = scene_ground()
    if a.elastic:
        layers = [Layer(l.thickness, l.density, l.shear_speed, l.poisson, 0.0) for l in layers]
    fe, resolved, dofs, seconds = fe_run(layers, band, along, a.f_mesh, a.fine)
    print("FE: %d DOFs, %.1f s" % (dofs, seconds))
    start = time.time()
    rayleigh = green_run(spectral.rayleigh_layers(layers, band[:2], band[2]), along, a.f_mesh)
    print("Green's functions: %.1f s" % (time.time() - start))
    report("FE against the Green's functions, the FE soil's Rayleigh law",
           differences(fe, rayleigh, resolved), resolved)
    if not a.elastic:
        hysteretic = green_run(layers, along, a.f_mesh)
        report("FE against the Green's functions, hysteretic (the Green's-function soil's law)",
               differences(fe, hysteretic, resolved), resolved)
        report("Green's functions: hysteretic against the Rayleigh law",
               differences(hysteretic, rayleigh, resolved), resolved)


if __name__ == "__main__":
    if "--measure" in sys.argv:
        measure(sys.argv[1:])
    else:
        unittest.main()
