#!/usr/bin/env python3
"""What the stability judgement costs beside the runs it judges, side by side
in one invocation (docs/benchmarks.md, "The verdict's cost").

Usage: judge_cost.py BIN_DIR SOURCE_DIR [--study DIR]

1. The paper study (`master study --scene scenes/paper.toml`, two workers),
   or an existing study folder with --study: the sum of every run's
   stability.map_s against the sum of its wall_s (the judgement's share),
   and the study's own wall time against its runs' wall time per worker.
2. The paper scene with 155 sleepers over 1 s and with 600 sleepers, one
   `master run --transport inproc` each: the judgement's seconds over the
   run's, the map's size, its measure and its verdict.
Each ratio's two numbers are measured in the same invocation; nothing is
divided by a baseline that holds the judgement.
"""
import json
import os
import subprocess
import sys
import tempfile
import time


def summaries(folder):
    for root, _, files in os.walk(folder):
        if "summary.json" in files and "monolithic" not in root.split(os.sep)[-1:]:
            with open(os.path.join(root, "summary.json")) as f:
                yield json.load(f)


def study_share(bin_dir, src, given):
    folder = given
    wall = None
    if not given:
        folder = tempfile.mkdtemp(prefix="judge_cost_study_")
        t0 = time.monotonic()
        subprocess.run([os.path.join(bin_dir, "master"), "study", "--scene",
                        os.path.join(src, "scenes", "paper.toml"), "--out", folder, "--jobs", "2"],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wall = time.monotonic() - t0
    runs = judged = 0.0
    count = 0
    for s in summaries(folder):
        runs += s.get("wall_s") or 0
        judged += (s.get("stability") or {}).get("map_s") or 0
        count += 1
    print("paper study: %d runs, their wall time %.1f s, the judgement's %.1f s: %.2f of the runs"
          % (count, runs, judged, judged / runs if runs else float("nan")))
    if wall is not None:
        print("  the study's wall time %.1f s over its runs' per worker (%.1f s): %.2f"
              % (wall, runs / 2, wall / (runs / 2)))


def scene_run(bin_dir, src, count, end_time):
    text = open(os.path.join(src, "scenes", "paper.toml")).read()
    text = text.replace("count = 50 ", "count = %d " % count, 1)
    text = text.replace("end_time = 0.25", "end_time = %g" % end_time, 1)
    work = tempfile.mkdtemp(prefix="judge_cost_%d_" % count)
    scene = os.path.join(work, "scene.toml")
    open(scene, "w").write(text)
    subprocess.run([os.path.join(bin_dir, "master"), "run", "--scene", scene, "--case", "rs-xx-jacobi",
                    "--transport", "inproc", "--out", work], check=False,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    s = json.load(open(os.path.join(work, "rs-xx-jacobi", "summary.json")))
    st = s["stability"]
    print("%d sleepers, %g s: run %.2f s, judgement %.2f s (%.2f of the run); map %s coordinates by %s, "
          "%s products; verdict %r"
          % (count, end_time, s["wall_s"], st.get("map_s") or 0, (st.get("map_s") or 0) / s["wall_s"],
             st.get("map_dimension"), st.get("map_method"), st.get("map_products"), st["verdict"]))


def main():
    bin_dir, src = sys.argv[1], sys.argv[2]
    given = sys.argv[sys.argv.index("--study") + 1] if "--study" in sys.argv else None
    study_share(bin_dir, src, given)
    scene_run(bin_dir, src, 155, 1.0)
    scene_run(bin_dir, src, 600, 0.25)


main()
