#!/usr/bin/env python3
"""The stability judgement on a model too large for the dense map, as a user
runs it: bounded and stoppable.

Usage: judge_bounds_test.py BIN_DIR SOURCE_DIR

- the paper scene with 600 sleepers (a map of about 8,000 coordinates, over
  the dense measure's 4,000): `master run` measures it by Arnoldi's method
  within its budget of products (the run's macro steps over two, at least
  200), and says "not judged" with the reason where Arnoldi proves nothing;
  its memory stays within 256 MiB of the same run with --judge none;
- SIGINT while it judges (a budget a thousand times the run's): the master
  ends within a few seconds (one product of the map is a few milliseconds),
  exit status 1, saying it was interrupted during the stability judgement;
  and on 155 sleepers, whose dense map's eigenvalues take seconds, within
  a second;
- --judge none and --judge stability: no reference is made, the status is
  not_judged and the message says why.
Exit status 0 when all hold; the first failure is printed.
"""
import json
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time


def fail(msg):
    sys.exit("FAIL: " + msg)


def interrupt(master, scene, work, out, extra, limit, wait=0.5):
    """Sends SIGINT `wait` s after the master says it judges; returns the
    seconds it took to end, which must be within `limit`."""
    cmd = [master, "run", "--scene", scene, "--case", "rs-xx-jacobi", "--transport", "inproc",
           "--out", os.path.join(work, out)] + extra
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seen = ""
    deadline = time.monotonic() + 300
    while "judging its stability" not in seen:
        line = proc.stderr.readline()
        if not line or time.monotonic() > deadline:
            proc.kill()
            fail("%s: no line saying the judgement began:\n%s" % (out, seen[-2000:]))
        seen += line
    time.sleep(wait)
    if proc.poll() is not None:
        fail("%s: the judgement ended before the signal; the test needs a longer one" % out)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        fail("%s: the master did not end within 10 s of SIGINT during the judgement" % out)
    took = time.monotonic() - sent
    said = seen + err
    if proc.returncode != 1:
        fail("%s: exit status %d after SIGINT during the judgement\n%s"
             % (out, proc.returncode, said[-2000:]))
    if "interrupted by signal 2 during the stability judgement" not in said:
        fail("%s: no clear message after SIGINT:\n%s" % (out, said[-2000:]))
    if took > limit:
        fail("%s: the master took %.2f s to end after SIGINT (at most %g s)" % (out, took, limit))
    return took


def main():
    bin_dir, src = sys.argv[1], sys.argv[2]
    master = os.path.join(bin_dir, "master")
    work = tempfile.mkdtemp(prefix="railcosim_judge_bounds_")
    text = open(os.path.join(src, "scenes", "paper.toml")).read()
    text = text.replace("count = 50 ", "count = 600 ", 1).replace("end_time = 0.25", "end_time = 0.05", 1)
    if "count = 600" not in text or "end_time = 0.05" not in text:
        fail("the paper scene's keys moved: sleepers.count or simulation.end_time not found")
    scene = os.path.join(work, "long.toml")
    open(scene, "w").write(text)

    def run(judge, budget=None, out="out"):
        cmd = [master, "run", "--scene", scene, "--case", "rs-xx-jacobi", "--transport", "inproc",
               "--judge", judge, "--out", os.path.join(work, out)]
        if budget is not None:
            cmd += ["--judge-budget", str(budget)]
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss  # KiB, the largest child so far
        summary = os.path.join(work, out, "rs-xx-jacobi", "summary.json")
        return p, (json.load(open(summary)) if os.path.exists(summary) else None), max(rss, before)

    p, none, rss_none = run("none", out="none")
    if p.returncode != 0 or none is None:
        fail("--judge none: exit %d\n%s" % (p.returncode, p.stderr[-2000:]))
    if none["status"] != "not_judged" or "--judge none" not in none["message"]:
        fail("--judge none: status %s, message %r" % (none["status"], none["message"]))
    if none["reference"]["kind"] != "none":
        fail("--judge none made a reference: %r" % none["reference"])

    p, full, rss_full = run("full", out="full")
    if p.returncode != 0 or full is None:
        fail("judged run: exit %d\n%s" % (p.returncode, p.stderr[-2000:]))
    st = full["stability"]
    steps = full["macro_steps"]
    if st["map_method"] != "krylov":
        fail("a map of 600 sleepers measured by %r, not Arnoldi's method" % st["map_method"])
    if st.get("map_solver") != "Spectra GenEigsSolver":
        fail("summary.json names the map's solver %r, not Spectra's" % st.get("map_solver"))
    budget = max(200, round(steps / 2))
    if not (0 < st["map_products"] <= budget):
        fail("%s products of the map, the budget is %d" % (st["map_products"], budget))
    if st["verdict"] == "not judged":
        if full["status"] != "not_judged" or "stability not judged:" not in full["message"]:
            fail("not judged, but status %s and message %r" % (full["status"], full["message"]))
        if "rho_not_judged" not in st:
            fail("not judged without the reason in summary.json: %r" % st)
    elif st["verdict"] != "unstable":
        fail("Arnoldi's method cannot prove a coupling stable, yet the verdict is %r" % st["verdict"])
    # ru_maxrss is the largest child so far: the judged run's peak is at
    # least the unjudged one's; the difference is the judgement's.
    if rss_full - rss_none > 256 * 1024:
        fail("the judgement took %d KiB above the unjudged run" % (rss_full - rss_none))

    # SIGINT while it judges: the Arnoldi measure of 600 sleepers, and the
    # dense map of 155 (2,954 coordinates: seconds of eigenvalues, asked
    # to stop from another thread).
    took = interrupt(master, scene, work, "stopped", ["--judge-budget", "1000"], limit=3)
    dense_scene = os.path.join(work, "dense.toml")
    open(dense_scene, "w").write(text.replace("count = 600 ", "count = 155 ", 1))
    took_dense = interrupt(master, dense_scene, work, "stopped_dense", [], limit=1.0, wait=1.5)

    p, stab, _ = run("stability", out="stab")
    if p.returncode != 0 or stab is None:
        fail("--judge stability: exit %d\n%s" % (p.returncode, p.stderr[-2000:]))
    if stab["reference"]["kind"] != "none" or stab["status"] not in ("not_judged", "amplified"):
        fail("--judge stability: status %s, reference %r" % (stab["status"], stab["reference"]))
    print("judge bounds: map of %s coordinates, %s products (budget %d), verdict %r, "
          "judgement %.0f MiB above the unjudged run, SIGINT ended it in %.2f s (Arnoldi) "
          "and %.2f s (dense)"
          % (st.get("map_dimension"), st["map_products"], budget, st["verdict"],
             (rss_full - rss_none) / 1024, took, took_dense))


main()
