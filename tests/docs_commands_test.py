#!/usr/bin/env python3
"""Every command in the README and docs/ against the programs it names.

Reads each shell block (```sh, ```bash, ```console, or unmarked) of
README.md and docs/*.md, joins continued lines, drops comments and a
trailing '&', adds the product commands written inline in the prose (a code
span that starts with build/bin/PROGRAM, its `> FILE` left out), and, in a
scratch folder that holds the repository's scenes,
checks each command as follows:

- the product's programs (build/bin/master, vehicle_node, track_node,
  soil_node, or the same installed, PREFIX/bin/master): run with --check
  (`master compare` on empty folders of the names it is given), which reads the command line and every file
  it names as the real command would, and must exit 0. HOST and PORT stand
  for 127.0.0.1 and a port; optional parts in [brackets] are left out of the
  run, and every --option they name must be one the program's --help lists;
- `sed ... > FILE` lines are run as written (the docs make scene variants
  that way, and later commands use them);
- Python modules and scripts (`python3 -m MODULE ...`, `python3 FILE.py
  ...`, also under mpirun): run for real with --help from the repository's
  root, which must exit 0 and print the usage, and every --option the
  command names (in [brackets] too) must be one that usage lists, so a
  renamed option fails here;
- the build's other programs (build/bin/BENCHMARK): a target some
  CMakeLists.txt makes;
- every other command (shell scripts, CMake, GNU parallel, Slurm): every
  path it names inside the repository (scenes/, scripts/, examples/,
  bench/, fe_soil/, docs/) must exist.

Then every `master run` command that can run cheaply (no node given by
address, no secret, not the FE soil, nothing optional) runs for real, as
written, in another scratch folder whose scenes end after 50 macro steps:
it must exit 0 and the first line of its output must be the summary of
its case ("CASE: STATUS, ..."), so a stale command fails here. A `--help`
must exit 0 and print the usage.

The scripts the README's two commands name are what CI runs.
Usage: docs_commands_test.py BIN_DIR SOURCE_DIR
"""

import glob
import os
import tomllib
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

PROGRAMS = ("master", "vehicle_node", "track_node", "soil_node")
SHELLS = ("sh", "bash", "console", "shell", "")
REPO_DIRS = ("scenes/", "scripts/", "examples/", "bench/", "fe_soil/", "docs/")
# At least this many product commands are checked: a change that breaks
# the reading of the docs fails here rather than checking nothing.
MIN_CHECKED = 25


def commands(path):
    """(line, command) for each command of the file's shell blocks."""
    lines = open(path, encoding="utf-8").read().split("\n")
    inside, lang, i = False, "", 0
    while i < len(lines):
        fence = re.match(r"^\s*```(\S*)", lines[i])
        if fence:
            inside, lang = not inside, fence.group(1)
        elif inside and lang in SHELLS:
            start, cmd = i + 1, lines[i].strip()
            while cmd.endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1].rstrip() + " " + lines[i].strip()
            if cmd.startswith("$ "):
                cmd = cmd[2:]
            cmd = re.sub(r"\s+#.*$", "", cmd)
            if cmd and not cmd.startswith("#"):
                yield start, cmd
        i += 1


def inline_commands(path):
    """(line, command) for each product command written inline, in a code
    span of the prose (`build/bin/master compare A B ...`), its output's
    redirection (`> FILE`) left out."""
    text = open(path, encoding="utf-8").read()
    prose = re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    for m in re.finditer(r"`([^`]+)`", prose):
        cmd = re.sub(r"\s*>\s*\S+$", "", " ".join(m.group(1).split()))
        if " " in cmd and product_program(cmd):
            yield prose.count("\n", 0, m.start()) + 1, cmd


def help_text(bin_dir, words):
    """--help of a program, or of the master's subcommand."""
    args = [os.path.join(bin_dir, words[0])]
    if words[0] == "master" and len(words) > 1 and not words[1].startswith("-"):
        args.append(words[1])
    out = subprocess.run(args + ["--help"], capture_output=True, text=True, timeout=30)
    return out.stdout + out.stderr


def check_program(bin_dir, cwd, cmd):
    """Runs a product command with --check; returns a failure or None."""
    optional = re.findall(r"\[([^\]]*)\]", cmd)
    concrete = re.sub(r"\s*\[[^\]]*\]", "", cmd)
    concrete = concrete.replace("HOST:PORT", "127.0.0.1:7099").replace(":PORT", ":7099")
    if concrete.rstrip().endswith("&"):
        concrete = concrete.rstrip()[:-1]
    words = shlex.split(concrete)
    words[0] = os.path.basename(words[0])
    known = help_text(bin_dir, words)
    for part in optional:
        for flag in re.findall(r"--[a-z][a-z-]*", part):
            if flag not in known:
                return "%s is not an option of %s" % (flag, " ".join(words[:2]))
    run = [os.path.join(bin_dir, words[0])] + words[1:]
    if "--help" in words:  # help wins over --check: it must print the usage
        out = subprocess.run(run, cwd=cwd, capture_output=True, text=True, timeout=60)
        return None if out.returncode == 0 and "Usage:" in out.stdout else \
            "exit %d: %s" % (out.returncode, (out.stdout + out.stderr).strip())
    if "--check" not in known:
        return "%s has no --check" % " ".join(words[:2])
    if words[1:2] == ["compare"]:  # the output folders it reads, empty, in a folder of its own
        cwd = tempfile.mkdtemp(prefix="docs-compare-")
        for folder in [w for w in words[2:4] if not w.startswith("-")]:
            os.makedirs(os.path.join(cwd, folder), exist_ok=True)
    out = subprocess.run(run + ["--check"], cwd=cwd, capture_output=True, text=True, timeout=60)
    if out.returncode != 0 or not out.stdout.startswith("check: "):
        return "exit %d: %s" % (out.returncode, (out.stdout + out.stderr).strip())
    return None


def product_program(cmd):
    """True for a command of the product's programs: build/bin/PROGRAM, or
    the installed PREFIX/bin/PROGRAM (the same program, installed)."""
    try:
        first = shlex.split(cmd)[0]
    except ValueError:  # not a command (an unbalanced quote in prose)
        return False
    name = os.path.basename(first)
    return name in PROGRAMS and (first.startswith("build/bin/") or first.endswith("/bin/" + name))


def check_target(source, program):
    """Another program of the build (a benchmark, a tool): a target some
    CMakeLists.txt of the repository makes, so a renamed one fails here."""
    name = os.path.basename(program)
    for path in glob.glob(os.path.join(source, "**", "CMakeLists.txt"), recursive=True):
        if re.search(r"add_executable\(\s*%s\s" % re.escape(name), open(path).read()):
            return None
    return "%s is not a program the build makes (no add_executable(%s ...))" % (program, name)


def check_paths(source, cmd):
    """The repository paths a command names exist."""
    for word in shlex.split(cmd.replace("<", " ").replace(">", " ")):
        word = word.split("=", 1)[-1]
        if word.startswith(REPO_DIRS) and "*" not in word:
            if not os.path.exists(os.path.join(source, word)):
                return "%s does not exist" % word
    return None


# Options a module's --help may leave out, as (module, option): none today
# (a program's own options reach the SDK's usage through serve's parents).
UNLISTED = set()


def python_target(cmd):
    """(target words, name) of a Python command, or None: `-m MODULE` or a FILE.py."""
    words = shlex.split(re.sub(r"\s*\[[^\]]*\]", "", cmd))
    for i, word in enumerate(words):
        if os.path.basename(word).startswith("python3"):
            rest = words[i + 1:]
            if rest[:1] == ["-m"] and len(rest) > 1:
                return ["-m", rest[1]], rest[1]
            if rest and rest[0].endswith(".py"):
                return [rest[0]], rest[0]
            return None
    return None


def check_python(source, cmd):
    """Runs a documented Python module or script with --help; returns a failure or None."""
    target, name = python_target(cmd)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([source, os.path.join(source, "sdk", "python")]))
    out = subprocess.run([sys.executable] + target + ["--help"], cwd=source, env=env,
                         capture_output=True, text=True, timeout=60)
    usage = out.stdout
    if out.returncode != 0 or not usage.startswith("usage:"):
        return "%s --help: exit %d: %s" % (name, out.returncode, (out.stdout + out.stderr).strip()[-800:])
    for flag in re.findall(r"(?<![\w-])--[a-z][a-z-]*", cmd):
        if flag not in re.findall(r"(?<![\w-])--[a-z][a-z-]*", usage) and (name, flag) not in UNLISTED:
            return "%s is not an option of %s (its --help)" % (flag, name)
    return None


def cheap_run(cmd):
    """A `master run` command that runs in seconds on shortened scenes."""
    words = cmd.split()
    return (len(words) > 1 and os.path.basename(words[0]) == "master" and words[1] == "run"
            and "--help" not in words and "[" not in cmd and "ground_vibration" not in cmd
            and not any(w in words for w in ("--node", "--vehicle", "--track", "--token-file")))


def shorten(folder):
    """Every scene in folder (and its scenes/) ends after 50 macro steps."""
    for path in glob.glob(os.path.join(folder, "*.toml")) + glob.glob(os.path.join(folder, "scenes", "*.toml")):
        text = open(path).read()
        try:
            h = tomllib.loads(text)["simulation"]["macro_step"]
        except (tomllib.TOMLDecodeError, KeyError):
            continue
        text = re.sub(r"(?m)^end_time\s*=\s*[0-9.eE+-]+", "end_time = %r" % (50 * h), text)
        open(path, "w").write(text)


def run_for_real(bin_dir, cwd, cmd):
    """Runs a cheap `master run` command as written; returns a failure or None."""
    words = shlex.split(cmd)
    case = words[words.index("--case") + 1]
    run = [os.path.join(bin_dir, "master")] + words[1:]
    out = subprocess.run(run, cwd=cwd, capture_output=True, text=True, timeout=120)
    first = (out.stdout.splitlines() or [""])[0]
    if out.returncode != 0 or not re.match(r"^%s: (ok|inaccurate|amplified|diverged|not_converged|not_judged), "
                                           % re.escape(case), first):
        return "run for real: exit %d, first line %r:\n%s" % (out.returncode, first, out.stderr[-1500:])
    return None


def main():
    bin_dir, source = sys.argv[1], sys.argv[2]
    docs = [os.path.join(source, "README.md")] + sorted(glob.glob(os.path.join(source, "docs", "*.md")))
    cwd = tempfile.mkdtemp(prefix="docs-commands-")
    failures, checked, paths, pythons, targets, real = [], 0, 0, 0, 0, []
    try:
        shutil.copytree(os.path.join(source, "scenes"), os.path.join(cwd, "scenes"))
        with open(os.path.join(cwd, "cosim.token"), "w") as f:
            f.write("a shared secret of the docs' examples\n")
        os.chmod(os.path.join(cwd, "cosim.token"), 0o600)  # the programs refuse others' reading
        os.mkdir(os.path.join(cwd, "study"))  # what `master study --collect study` reads
        for doc in docs:
            name = os.path.relpath(doc, source)
            for line, cmd in list(commands(doc)) + list(inline_commands(doc)):
                first = cmd.split()[0]
                if product_program(cmd):
                    why = check_program(bin_dir, cwd, cmd)
                    checked += 1
                    if cheap_run(cmd):
                        real.append((name, line, cmd))
                elif first.startswith("build/bin/"):
                    why = check_target(source, first)
                    targets += 1
                elif first == "sed" and ">" in cmd:
                    out = subprocess.run(cmd, shell=True, cwd=cwd, capture_output=True, text=True)
                    why = out.stderr.strip() if out.returncode else None
                elif python_target(cmd):
                    why = check_paths(source, cmd) or check_python(source, cmd)
                    pythons += 1
                else:
                    why = check_paths(source, cmd)
                    paths += 1
                if why:
                    failures.append("%s:%d: %s\n    %s" % (name, line, cmd, why))
        # --check writes nothing: no run folder, plan or report appeared.
        made = sorted(set(os.listdir(cwd)) - {"scenes", "cosim.token", "study"})
        if any(not name.endswith(".toml") for name in made):
            failures.append("--check wrote into the working folder: %s" % ", ".join(made))
        if os.listdir(os.path.join(cwd, "study")):
            failures.append("--check wrote into study/: %s" % os.listdir(os.path.join(cwd, "study")))
        # The cheap runs for real, on shortened copies of the scenes.
        shorten(cwd)
        for name, line, cmd in real:
            why = run_for_real(bin_dir, cwd, cmd)
            if why:
                failures.append("%s:%d: %s\n    %s" % (name, line, cmd, why))
    finally:
        shutil.rmtree(cwd, ignore_errors=True)
    print("%d commands of the product checked with --check (%d of them run for real), %d Python "
          "modules and scripts run with --help, %d other programs of the build found among its "
          "targets, %d others' paths checked" % (checked, len(real), pythons, targets, paths))
    if checked < MIN_CHECKED:
        failures.append("only %d product commands found (at least %d expected): the reading of "
                        "the docs' shell blocks is broken" % (checked, MIN_CHECKED))
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
