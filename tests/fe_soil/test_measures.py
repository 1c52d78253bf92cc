"""The vibration measures against closed forms."""
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", ".."))
from fe_soil import measures, resolution  # noqa: E402


def sine(amplitude, f, duration, dt):
    t = np.arange(int(round(duration / dt))) * dt
    return t, amplitude * np.sin(2.0 * math.pi * f * t)


class Measures(unittest.TestCase):
    def test_ppv_of_a_sine_is_its_amplitude(self):
        _, v = sine(3e-4, 12.5, 2.0, 1e-3)
        self.assertAlmostEqual(measures.ppv(v), 3e-4, delta=3e-4 * 1e-6)
        v3 = np.stack([v, -2.0 * v, 0.5 * v], axis=1)
        self.assertAlmostEqual(measures.ppv(v3), 6e-4, delta=6e-4 * 1e-6)

    def test_low_passed_keeps_what_lies_below_and_takes_out_what_lies_above(self):
        dt, n = 1e-3, 4000
        t = np.arange(n) * dt
        below, above = np.sin(2 * np.pi * 10.0 * t), np.sin(2 * np.pi * 40.0 * t)
        out = measures.low_passed(below + above, dt, 20.0)  # flat to 15.9 Hz, zero from 20
        inner = slice(n // 4, 3 * n // 4)  # away from the record's ends
        self.assertLess(float(np.abs(out - below)[inner].max()), 1e-3)
        # the record's start is not wrapped onto by its end: a late pulse stays late
        pulse = np.exp(-((t - 3.5) / 0.05) ** 2)
        self.assertLess(float(np.abs(measures.low_passed(pulse, dt, 20.0)[:n // 2]).max()), 1e-6)
        np.testing.assert_array_equal(measures.low_passed(above, dt, 0.0), above)

    def test_bands_are_base_ten_thirds_from_1_to_100_hz(self):
        fc, lo, hi = measures.third_octave_bands()
        self.assertEqual(len(fc), 21)
        self.assertAlmostEqual(fc[0], 1.0)
        self.assertAlmostEqual(fc[-1], 100.0)
        np.testing.assert_allclose(hi[:-1], lo[1:], rtol=1e-12)

    def test_band_level_of_a_sine_at_a_band_centre(self):
        # 10 Hz is a band centre; 2 s at 1 kHz holds 20 whole periods, so the
        # whole power sits in one bin: L = 20 log10(A / sqrt(2) / 1e-9).
        amplitude = 1e-4
        _, v = sine(amplitude, 10.0, 2.0, 1e-3)
        fc, levels = measures.third_octave_levels(v, 1e-3)
        k = int(np.argmin(abs(fc - 10.0)))
        expected = 20.0 * math.log10(amplitude / math.sqrt(2.0) / 1e-9)
        self.assertAlmostEqual(levels[k], expected, delta=1e-9)
        others = np.delete(levels, k)
        self.assertTrue(np.all(others < expected - 200.0), others)

    def test_band_levels_hold_the_total_mean_square(self):
        rng = np.random.default_rng(3)
        # Power only between 1 and 100 Hz: sum of band mean squares = mean square.
        dt, n = 1e-3, 4000
        freq = np.fft.rfftfreq(n, dt)
        spec = rng.standard_normal(len(freq)) + 1j * rng.standard_normal(len(freq))
        spec[(freq < 0.9) | (freq > 110.0)] = 0.0
        v = np.fft.irfft(spec, n)
        _, rms = measures.band_rms(v, dt)
        self.assertAlmostEqual(float((rms**2).sum()), float((v**2).mean()), delta=1e-12 * (v**2).mean())

    def test_kb_f_of_a_sine(self):
        # A sine of amplitude A (m/s) at f: KB = 1e3 A / sqrt(1 + (f0/f)^2) in
        # amplitude; the exponential running mean of KB^2 settles to
        # KB^2/2 (1 + cos(2 w t - phi) / sqrt(1 + (2 w tau)^2)), so
        # KB_Fmax = KB / sqrt(2) * sqrt(1 + 1 / sqrt(1 + (2 w tau)^2)).
        amplitude, dt = 2e-4, 2e-4
        for f in (4.0, 8.0, 31.5):
            _, v = sine(amplitude, f, 3.0, dt)
            kb = 1e3 * amplitude / math.sqrt(1.0 + (5.6 / f) ** 2)
            w = 2.0 * math.pi * f
            expected = kb / math.sqrt(2.0) * math.sqrt(1.0 + 1.0 / math.sqrt(1.0 + (2.0 * w * 0.125) ** 2))
            self.assertAlmostEqual(measures.kb_fmax(v, dt), expected, delta=5e-3 * expected, msg=f"f = {f} Hz")
            steady = measures.kb_f(v, dt)[int(2.0 / dt) :]
            self.assertAlmostEqual(float(np.mean(steady**2)), kb**2 / 2.0, delta=5e-3 * kb**2)

    def test_kb_weighting_at_the_corner_frequency(self):
        # |H_KB(f0)| = 1/sqrt(2).
        dt = 1e-4
        _, v = sine(1e-3, 5.6, 4.0, dt)
        y = measures.kb_weighting(v, dt)[int(2.0 / dt) :]
        self.assertAlmostEqual(float(np.max(np.abs(y))), 1.0 / math.sqrt(2.0), delta=2e-3)

    def test_receiver_summary_per_component(self):
        dt = 1e-3
        _, vz = sine(2e-4, 10.0, 2.0, dt)
        v = np.stack([0.5 * vz, 0.0 * vz, vz], axis=1)
        s = measures.receiver_summary(v, dt)
        self.assertAlmostEqual(s["ppv"], 2e-4, delta=1e-12)
        self.assertEqual(len(s["band_centres"]), 21)
        k = s["band_centres"].index(min(s["band_centres"], key=lambda f: abs(f - 10.0)))
        self.assertAlmostEqual(s["band_levels"][0][k] - s["band_levels"][2][k], 20.0 * math.log10(0.5), delta=1e-9)
        self.assertAlmostEqual(s["kb_fmax"][0] / s["kb_fmax"][2], 0.5, delta=1e-9)
        self.assertEqual(s["kb_fmax"][1], 0.0)

    def test_resolved_bands_from_the_band_edges(self):
        # Band m: centre 10^(m/10), edges 10^((m -+ 1/2)/10), width 0.2308
        # of the centre. 1 s: the 5 Hz band (1.16 Hz wide) holds a line, the
        # 4 Hz band (0.92 Hz) may not; 24 Hz: the 20 Hz band ends at 22.4
        # Hz, the 25 Hz band at 28.2 Hz. 0.1 s: 10 Hz apart, the 50 Hz band
        # first (11.5 Hz wide).
        def band(m):
            return 10.0 ** (m / 10.0)

        for top, record, lo, hi in ((24.0, 1.0, 7, 13), (band(13.5), 1.0, 7, 13),
                                    (100.0, 0.1, 17, 19), (200.0, 0.1, 17, 20)):
            np.testing.assert_allclose(resolution.resolved_bands(top, record), (band(lo), band(hi)),
                                       rtol=1e-14)
        for top, record in ((24.0, 0.02), (40.0, 0.1), (0.0, 1.0)):
            self.assertTrue(all(map(math.isnan, resolution.resolved_bands(top, record))))

    def test_vibration_csv_ends_with_the_resolved_bands(self):
        s = measures.receiver_summary(np.zeros((100, 3)), 1e-2)
        text = measures.with_resolved(
            measures.vibration_csv(["a", "b"], [1.0, 1.0], [4.0, 8.0], [s, s]),
            [(5.0, 20.0), (math.nan, math.nan)])
        rows = [line.split(",") for line in text.splitlines()]
        self.assertEqual(rows[0][-3:], ["Lv_z_100Hz_dB", "resolved_from_hz", "resolved_to_hz"])
        self.assertEqual(rows[1][-2:], ["5", "20"])
        self.assertEqual(rows[2][-2:], ["nan", "nan"])
        self.assertEqual(len({len(r) for r in rows}), 1)
        self.assertTrue(text.endswith("\n") and not text.endswith("\n\n"))


if __name__ == "__main__":
    unittest.main()
