#!/usr/bin/env python3
"""Progress of long work, as a user sees it.

Usage: progress_test.py BIN_DIR SOURCE_DIR

- `master run` with stderr on a pseudo-terminal: one line redrawn in place
  ("\\r" ... ESC[K) with the runs done of all, the macro step of all, the
  time elapsed and the time left, ended by a newline; stdout (a pipe) holds
  the summary alone; the nodes the master starts are not announced unless
  --verbose;
- the same with stderr a pipe: plain "progress: " lines, one per
  RAILCOSIM_PROGRESS_SECONDS, and no terminal control characters;
- `master study` on a pseudo-terminal: the runs done of all, up to all;
- the ground-vibration study's progress (fe_soil/progress.py) on a
  pseudo-terminal and a pipe, and its reading of a master run's lines
  (fe_soil.study.run_master against the real master).
Exit status 0 when all hold; the first failure is printed.
"""
import os
import pty
import re
import shutil
import subprocess
import sys
import tempfile
import time

ELAPSED = r"elapsed \d+:\d\d"
LEFT = r"(, about \d+:\d\d left|, time left not yet known)"


def fail(msg):
    sys.exit("FAIL: " + msg)


def on_pty(cmd, env=None, timeout=240):
    """Runs cmd with stderr on a pseudo-terminal, stdout a pipe: (status,
    stdout, what the terminal got)."""
    master_fd, slave_fd = pty.openpty()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=slave_fd, stdin=subprocess.DEVNULL,
                         env=env)
    os.close(slave_fd)
    got = b""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            chunk = os.read(master_fd, 65536)
        except OSError:  # the other end closed: the program ended
            break
        if not chunk:
            break
        got += chunk
    os.close(master_fd)
    out = p.stdout.read().decode()
    try:
        status = p.wait(timeout=max(1.0, deadline - time.monotonic()))
    except subprocess.TimeoutExpired:
        p.kill()
        fail("%s did not end within %d s" % (" ".join(cmd), timeout))
    return status, out, got.decode(errors="replace").replace("\r\n", "\n")


def master_run(bin_dir, work):
    base = [os.path.join(bin_dir, "master"), "run", "--scene", os.path.join(work, "paper.toml"),
            "--case", "rs-xx-jacobi", "--macro-step", "1e-5"]
    status, out, tty = on_pty(base + ["--out", os.path.join(work, "tty")])
    if status != 0:
        fail("master run on a terminal exited %d:\n%s%s" % (status, out, tty))
    steps = [int(m.group(1)) for m in re.finditer(
        r"\rrs-xx-jacobi: 0/1 run done; rs-xx-jacobi step (\d+)/10000; " + ELAPSED + LEFT + "\x1b\\[K", tty)]
    if not any(0 < s < 10000 for s in steps):
        fail("no progress line in place with the step of all, elapsed and left:\n%r" % tty[-2000:])
    if not re.search(r"\rrs-xx-jacobi: 1/1 run done; " + ELAPSED + "\x1b\\[K\n", tty):
        fail("the progress line does not end with the run done and a newline:\n%r" % tty[-500:])
    if not out.startswith("rs-xx-jacobi: ok") or "\r" in out or "progress:" in out:
        fail("stdout is not the summary alone:\n%r" % out)
    if "started " in tty:
        fail("the node start-up is announced without --verbose:\n%s" % tty)
    _, _, verbose = on_pty(base + ["--out", os.path.join(work, "verbose"), "--verbose"])
    if "started vehicle_node for the vehicle participant on 127.0.0.1:" not in verbose:
        fail("--verbose does not announce the nodes:\n%s" % verbose[-1000:])

    env = dict(os.environ, RAILCOSIM_PROGRESS_SECONDS="0.05")
    p = subprocess.run(base + ["--out", os.path.join(work, "pipe")], capture_output=True, text=True,
                       env=env, timeout=240)
    lines = [l for l in p.stderr.splitlines() if l.startswith("progress: ")]
    pattern = r"progress: rs-xx-jacobi: 0/1 run done; rs-xx-jacobi step (\d+)/10000; " + ELAPSED + LEFT + "$"
    if p.returncode != 0 or not any(re.match(pattern, l) for l in lines):
        fail("no plain progress line on a pipe (exit %d):\n%s" % (p.returncode, p.stderr[-2000:]))
    if "\r" in p.stderr or "\x1b" in p.stderr:
        fail("terminal control characters on a pipe:\n%r" % p.stderr[-500:])
    if not p.stdout.startswith("rs-xx-jacobi: ok"):
        fail("stdout is not the summary:\n%s" % p.stdout)


def master_study(bin_dir, work):
    cmd = [os.path.join(bin_dir, "master"), "study", "--scene", os.path.join(work, "short.toml"), "--out",
           os.path.join(work, "study"), "--jobs", "2", "--macro-steps", "1e-4,5e-4", "--tolerances", "1e-6",
           "--transport", "inproc"]
    status, out, tty = on_pty(cmd)
    if status != 0:
        fail("master study exited %d:\n%s%s" % (status, out, tty[-2000:]))
    total = re.search(r"stage 1: (\d+) runs on 2 worker", tty)
    if not total:
        fail("the study does not say its runs:\n%s" % tty[-2000:])
    n = int(total.group(1))
    if not re.search(r"\rstudy, stage 1: %d/%d runs done; " % (n, n) + ELAPSED + "\x1b\\[K\n", tty):
        fail("the study's line does not end with %d/%d runs done:\n%r" % (n, n, tty[-1000:]))
    done = [int(m) for m in re.findall(r"\rstudy, stage 1: (\d+)/%d runs done" % n, tty)]
    if done != sorted(done) or len(set(done)) < 2:
        fail("the runs done do not count up: %s" % done)
    if not out.startswith("study of "):
        fail("stdout does not start with the study's result:\n%s" % out[:500])


def fe_progress(bin_dir, src, work):
    sys.path.insert(0, src)
    from fe_soil import progress
    now = [0.0]
    master_fd, slave_fd = pty.openpty()
    with open(slave_fd, "w") as tty:
        pr = progress.Progress("ground-vibration study", 4, stream=tty, clock_fn=lambda: now[0])
        pr.begin("Jacobi")
        now[0] = 30.0
        pr.at(500, 2000)  # a quarter of the first of four: 1/16 done in 30 s
        pr.end()
    text = b""
    while True:
        try:
            chunk = os.read(master_fd, 4096)
        except OSError:  # the terminal's other end is closed: all read
            break
        if not chunk:
            break
        text += chunk
    os.close(master_fd)
    text = text.decode()
    want = "\rground-vibration study: 0/4 runs done; Jacobi step 500/2000; elapsed 0:30, about 7:30 left\x1b[K"
    if want not in text:
        fail("the FE study's line on a terminal: %r, wanted %r in it" % (text, want))
    r, w = os.pipe()
    with open(w, "w") as pipe:
        now[0] = 0.0
        os.environ["RAILCOSIM_PROGRESS_SECONDS"] = "10"
        pr = progress.Progress("ground-vibration study", 4, stream=pipe, clock_fn=lambda: now[0])
        pr.begin("Jacobi")
        now[0] = 5.0
        pr.at(100, 2000)  # before the period: nothing
        now[0] = 10.0
        pr.at(1000, 2000)
    lines = os.read(r, 4096).decode().splitlines()
    os.close(r)
    if lines != ["progress: ground-vibration study: 0/4 runs done; Jacobi step 1000/2000; elapsed 0:10, "
                 "about 1:10 left"]:
        fail("the FE study's plain lines: %s" % lines)
    # run_master reads a real master run's progress lines.
    from fe_soil import study

    class Steps:
        seen = []

        def at(self, step, steps):
            self.seen.append((step, steps))

    rec = Steps()
    os.environ["RAILCOSIM_PROGRESS_SECONDS"] = "0.05"
    study.run_master(os.path.join(bin_dir, "master"), os.path.join(work, "paper.toml"), os.path.join(work, "fe"),
                     "rs-xx-jacobi", ["--macro-step", "1e-5", "--transport", "inproc"], rec)
    if not rec.seen or any(t != 10000 or not 0 < s <= 10000 for s, t in rec.seen):
        fail("run_master read no progress of the master run: %s" % rec.seen)
    log = open(os.path.join(work, "fe", "master.log")).read()
    if "progress: " in log or "rs-xx-jacobi: ok" not in log:
        fail("master.log: %s" % log[-500:])


def main(bin_dir, src):
    work = tempfile.mkdtemp(prefix="railcosim_pt_")
    try:
        text = open(os.path.join(src, "scenes", "paper.toml")).read()
        paper, n = re.subn(r"(?m)^end_time\s*=\s*[0-9.eE+-]+", "end_time = 0.1", text)
        short, _ = re.subn(r"(?m)^end_time\s*=\s*[0-9.eE+-]+", "end_time = 0.005", text)
        if n != 1:
            fail("scenes/paper.toml: no end_time line")
        open(os.path.join(work, "paper.toml"), "w").write(paper)
        open(os.path.join(work, "short.toml"), "w").write(short)
        master_run(bin_dir, work)
        master_study(bin_dir, work)
        fe_progress(bin_dir, src, work)
        print("ok: progress on a terminal and on a pipe, master run, master study and the FE study")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
