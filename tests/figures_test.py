#!/usr/bin/env python3
"""The study's figures and its answer, end to end on one shipped scene.

Usage: figures_test.py BIN_DIR SCENE

Runs a real, reduced study of SCENE (t_end cut to 5 ms, macro steps 1e-4 and
5e-4 s, one tolerance, in process) with `master study`, then checks that
  - every figure was drawn (a PNG file) and the report links it;
  - the front the speed/accuracy chart draws (figures.py --print-front,
    each point read from summary.csv) is the report's "Cheapest method per
    accuracy" table, row for row, and the answer the report opens with;
  - each point of that front is the cheapest run of its cut and transport
    that ends ok within its error level (the rule, checked on summary.csv).
Exit status 0 when all hold; the first failure is printed.
"""
import csv
import os
import re
import shutil
import subprocess
import sys
import tempfile

FIGURES = ("deflection", "errors", "speed_accuracy", "stability_map", "contact_force")


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def table_rows(report, heading):
    """The rows of the first table after `heading`, as lists of cells."""
    at = report.find(heading)
    if at < 0:
        fail(f"REPORT.md has no '{heading}'")
    rows = []
    for line in report[at:].splitlines()[1:]:
        if line.startswith("|"):
            rows.append([c.strip() for c in line.strip("|").split("|")])
        elif rows:
            break
    return rows[2:]  # past the header and the rule


def sci(v):
    return f"{v:.2e}"


def main(bin_dir, scene):
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    work = tempfile.mkdtemp(prefix="railcosim_figures_")
    try:
        text = open(scene).read()
        short, n = re.subn(r"(?m)^end_time\s*=\s*[0-9.eE+-]+", "end_time = 0.005", text)
        if n != 1:
            fail(f"{scene}: no end_time line to shorten")
        short_scene = os.path.join(work, os.path.basename(scene))
        with open(short_scene, "w") as f:
            f.write(short)
        out = os.path.join(work, "out")
        cmd = [os.path.join(bin_dir, "master"), "study", "--scene", short_scene, "--out", out, "--jobs", "2",
               "--macro-steps", "1e-4,5e-4", "--tolerances", "1e-6", "--transport", "inproc"]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            fail(f"{' '.join(cmd)} exited {p.returncode}:\n{p.stdout}{p.stderr}")
        report = open(os.path.join(out, "REPORT.md")).read()
        if "Figures were not drawn" in report:
            fail("the study drew no figures:\n" + p.stdout + p.stderr)
        figs = FIGURES + (("spectra",) if os.path.exists(os.path.join(out, "monolithic", "spectra.csv")) else ())
        for fig in figs:
            path = os.path.join(out, "figures", fig + ".png")
            if not os.path.exists(path) or open(path, "rb").read(8) != b"\x89PNG\r\n\x1a\n":
                fail(f"{path}: not a PNG")
            if f"figures/{fig}.png" not in report:
                fail(f"REPORT.md does not show {fig}.png")

        # The front the chart draws, from the same study folder.
        q = subprocess.run(["/usr/bin/python3", os.path.join(src, "scripts", "figures.py"), "--print-front", out],
                           capture_output=True, text=True)
        if q.returncode != 0:
            fail(f"figures.py --print-front failed:\n{q.stderr}")
        drawn = list(csv.DictReader(q.stdout.splitlines()))
        drawn_keys = [(d["cut"], sci(float(d["level"])), d["method"], float(d["macro_step_s"]),
                       sci(float(d["wall_s"])), sci(float(d["error"]))) for d in drawn]

        table = [r for r in table_rows(report, "## Cheapest method per accuracy") if r[0] != "monolithic"]
        table_keys = [(r[0], r[1], r[2], float(r[3]), r[6], r[5]) for r in table if r[3]]
        if not table_keys:
            fail("the cheapest-method table names no co-simulation run")
        if drawn_keys != table_keys:
            fail(f"the chart's front differs from the report's table:\n drawn {drawn_keys}\n table {table_keys}")

        # The answer the report opens with: before the first section, each
        # cut's cell names the same method and H.
        opening = report[: report.find("\n## ")]
        answer = table_rows(opening, "**The answer.**")
        header = opening[opening.find("| error at most |"):].splitlines()[0].strip("|").split("|")
        header = [h.strip() for h in header]
        for cut, level, method, h, _, _ in drawn_keys:
            row = next((a for a in answer if sci(float(a[0])) == level), None)
            # The study runs in process: every co-simulation column is its cut's.
            col = header.index(f"{cut} cut") if f"{cut} cut" in header else -1
            if row is None or col < 0 or f"`{method}`, H = {h:g} s" not in row[col]:
                fail(f"the report's opening answer lacks {method} at H = {h:g} s for {cut} at {level}")

        # The rule: nothing of the same cut that ends ok within the level is cheaper.
        sys.path.insert(0, os.path.join(src, "scripts"))
        import figures  # noqa: E402
        runs = list(csv.DictReader(open(os.path.join(out, "summary.csv"))))
        for d in drawn:
            level, wall = float(d["level"]), float(d["wall_s"])
            if float(d["error"]) > level:
                fail(f"{d['method']} drawn at {d['level']} with error {d['error']}")
            for r in runs:
                if (r["group"] in ("case", "sweep") and r["method"] != "monolithic"
                        and figures.cut_of(r["method"]) == d["cut"] and r["status"] == "ok"
                        and r["transport"] == d["transport"]
                        and r["rel_l2_error_converged"] and float(r["rel_l2_error_converged"]) <= level
                        and float(r["wall_s"]) < wall):
                    fail(f"{r['folder']} ({r['wall_s']} s) is cheaper than the front's {d['method']} at {level}")
        print(f"ok: {os.path.basename(scene)}: {len(drawn)} front points, {len(figs)} figures")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
