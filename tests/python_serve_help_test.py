#!/usr/bin/env python3
"""The Python SDK's serve() explains every option of its command line: the
example soil's --help lists --listen, --config, --table, --token-file,
--relayed-only, --name and --check-configure, each with a sentence of help
(not the bare option argparse prints without one), and names the master's
--node. Usage: python_serve_help_test.py SOURCE_DIR"""

import os
import re
import subprocess
import sys

src = sys.argv[1]
OPTIONS = ("--listen", "--config", "--table", "--token-file", "--relayed-only", "--name",
           "--check-configure")
out = subprocess.run([sys.executable, os.path.join(src, "examples", "python_soil",
                                                   "soil_participant.py"), "--help"],
                     capture_output=True, text=True, timeout=60,
                     env=dict(os.environ, COLUMNS="100"))
failures = []
if out.returncode != 0 or not out.stdout.startswith("usage:"):
    failures.append("--help: exit %d: %s" % (out.returncode, out.stderr))
text = out.stdout
# Each option's entry: its line of the options section and the lines under it.
entries, current = {}, None
for line in text.split("options:", 1)[-1].split("\n"):
    if re.match(r"^  -", line):
        current = [line]
        for n in re.findall(r"--[a-z-]+", line.split("  ")[1]):
            entries[n] = current
    elif current is not None and line.startswith("    "):
        current.append(line)
for o in OPTIONS:
    if o not in entries:
        failures.append("%s is not listed in --help" % o)
        continue
    first = re.sub(r"^  (-\S+( [A-Z:]+)?,? ?)+", "", entries[o][0])  # the option and metavar
    helptext = " ".join([first] + entries[o][1:]).split()
    if len(helptext) < 5:
        failures.append("%s has no help text: %r" % (o, " ".join(entries[o]).strip()))
if "--node soil=HOST:PORT" not in " ".join(text.split()):
    failures.append("--help does not say how the master reaches it (--node soil=HOST:PORT)")
for f in failures:
    print("FAIL " + f)
sys.exit(1 if failures else 0)
