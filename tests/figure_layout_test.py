#!/usr/bin/env python3
"""The study's speed/accuracy chart and stability map are readable: drawn
(matplotlib Agg) from a small synthetic study of 4 and of 12 methods over 4
macro steps (and of 4 methods of one cut, a one-panel chart), every text of each figure (titles, legend, labels, ticks,
table cells) lies inside the figure's canvas, and no two method labels of a
panel overlap. The synthetic methods of a cut sit close together, as a real
study's do (Jacobi and Gauss-Seidel of one split a few per cent apart).
Usage: figure_layout_test.py SOURCE_DIR"""

import csv
import itertools
import os
import shutil
import sys
import tempfile
import unittest

SRC = os.path.abspath(sys.argv.pop(1))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402

import figures  # noqa: E402
import speed_accuracy  # noqa: E402

STEPS = (1e-5, 1e-4, 5e-4, 1e-3)
CASES = ("rs-xx-jacobi", "rs-xx-gauss-seidel", "wr-xt-jacobi", "wr-xt-gauss-seidel")
VARIANTS = ("", "+explicit-extrapolate1", "+implicit-waveform3-iqn-ils")
FIELDS = ("group", "folder", "method", "status", "wall_s", "rel_l2_error_converged", "transport",
          "macro_step_s", "tolerance_m")


ONE_CUT = ("rs-xx-jacobi", "rs-xx-gauss-seidel", "rs-xt-jacobi", "rs-xt-gauss-seidel")


def methods(n):
    """n methods over two cuts; -4: four methods of one cut (a one-panel chart)."""
    return list(ONE_CUT) if n == -4 else [c + v for v in VARIANTS for c in CASES][:n]


def write_study(folder, n):
    """summary.csv and front.csv of a study of n methods: each method's runs
    over STEPS, errors falling with H, methods of a cut a few per cent apart."""
    rows = []
    for k, m in enumerate(methods(n)):
        for j, h in enumerate(STEPS):
            status = "amplified" if (m.endswith("wr-xt-jacobi") and h == STEPS[-1]) else "ok"
            rows.append({"group": "case" if j == 1 else "sweep", "folder": "%s/H%d" % (m, j),
                         "method": m, "status": status,
                         "wall_s": 0.02 / h * 1e-4 * (1 + 0.03 * k),
                         "rel_l2_error_converged": 0.5 * (h / 1e-3) * (1 + 0.05 * k),
                         "transport": "tcp" if "waveform" not in m else "inproc",
                         "macro_step_s": h, "tolerance_m": 1e-7})
    for j, tol in enumerate((1e-5, 1e-6, 1e-7, 1e-8)):
        rows.append({"group": "tolerance" if j else "case", "folder": "monolithic/T%d" % j,
                     "method": "monolithic", "status": "ok", "wall_s": 0.01 * 2 ** j,
                     "rel_l2_error_converged": tol * 10, "transport": "inproc",
                     "macro_step_s": 1e-4, "tolerance_m": tol})
    with open(os.path.join(folder, "summary.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, FIELDS)
        w.writeheader()
        w.writerows(rows)
    front = []
    for cut in sorted({speed_accuracy.cut_of(m) for m in methods(n)}):
        mine = [r for r in rows if speed_accuracy.cut_of(r["method"]) == cut and r["status"] == "ok"]
        for level in (1e-1, 1e-2, 1e-3):
            ok = [r for r in mine if r["rel_l2_error_converged"] <= level]
            best = min(ok, key=lambda r: r["wall_s"]) if ok else None
            front.append({"cut": cut, "level": level, "method": best["method"] if best else "",
                          "folder": best["folder"] if best else "", "transport": "tcp"})
    with open(os.path.join(folder, "front.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, ("cut", "level", "method", "folder", "transport"))
        w.writeheader()
        w.writerows(front)
    return rows


class Drawn:
    """Every figure saved while it is active, kept open for the checks."""

    def __enter__(self):
        self.figures, self.save = [], Figure.savefig

        def save(fig, *a, **k):
            self.save(fig, *a, **k)
            self.figures.append((os.path.basename(a[0]) if a else "?", fig))
        Figure.savefig = save
        return self

    def __exit__(self, *exc):
        Figure.savefig = self.save


class Layout(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="figure_layout_")

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def draw(self, n):
        rows = write_study(self.dir, n)
        with Drawn() as d:
            speed_accuracy.speed_accuracy(self.dir, rows_as_read(self.dir), self.dir)
            figures.stability_map(rows_as_read(self.dir), self.dir)
        self.assertEqual(sorted(name for name, _ in d.figures), ["speed_accuracy.png", "stability_map.png"])
        return dict(d.figures), rows

    def check_inside(self, name, fig):
        """Every drawn text inside the canvas: the figure's own texts and
        legends, each axes' texts and tables, and each axes' tight box (its
        title, axis labels and the tick labels it draws)."""
        r = fig.canvas.get_renderer()
        box = fig.bbox

        def inside(what, e):
            ok = e.x0 >= box.x0 - 1 and e.x1 <= box.x1 + 1 and e.y0 >= box.y0 - 1 and e.y1 <= box.y1 + 1
            self.assertTrue(ok, "%s: %s at %s is outside the figure %s" % (name, what, e.bounds, box.bounds))

        for t in fig.texts:
            if t.get_visible() and t.get_text().strip():
                inside(repr(t.get_text()[:60]), t.get_window_extent(r))
        for g in fig.legends:
            inside("the legend", g.get_window_extent(r))
        for ax in fig.axes:
            inside("the axes %r with its labels" % ax.get_title()[:40], ax.get_tightbbox(r))
            for t in ax.texts:
                if t.get_visible() and t.get_text().strip():
                    inside(repr(t.get_text()[:60]), t.get_window_extent(r))
            for table in ax.tables:
                inside("the table", table.get_window_extent(r))

    def check_labels(self, fig, n):
        r = fig.canvas.get_renderer()
        labels = {speed_accuracy.short_name(m, speed_accuracy.cut_of(m)) for m in methods(n)}
        for ax in fig.axes:
            mine = [t for t in ax.texts if t.get_visible() and t.get_text() in labels]
            for a, b in itertools.combinations(mine, 2):
                ea, eb = a.get_window_extent(r), b.get_window_extent(r)
                self.assertFalse(ea.overlaps(eb), "%r and %r overlap (%s, %s)" % (a.get_text(), b.get_text(),
                                                                                  ea.bounds, eb.bounds))
            if ax.get_title():
                drawn = {t.get_text() for t in mine}
                want = {speed_accuracy.short_name(m, speed_accuracy.cut_of(m)) for m in methods(n)
                        if ax.get_title().startswith(speed_accuracy.cut_of(m) + ":")}
                self.assertEqual(drawn, want, ax.get_title())

    def test_four_methods(self):
        figs, _ = self.draw(4)
        for name, fig in figs.items():
            self.check_inside(name, fig)
        self.check_labels(figs["speed_accuracy.png"], 4)

    def test_four_methods_of_one_cut(self):
        figs, _ = self.draw(-4)
        for name, fig in figs.items():
            self.check_inside(name, fig)
        self.check_labels(figs["speed_accuracy.png"], -4)

    def test_twelve_methods(self):
        figs, _ = self.draw(12)
        for name, fig in figs.items():
            self.check_inside(name, fig)
        self.check_labels(figs["speed_accuracy.png"], 12)


def rows_as_read(folder):
    return speed_accuracy.read_rows(os.path.join(folder, "summary.csv"))


if __name__ == "__main__":
    unittest.main()
