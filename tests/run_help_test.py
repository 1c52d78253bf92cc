#!/usr/bin/env python3
"""`master run --help` lists every key of the scene's [coupling] table with
the flag it stands in for (the keys as docs/scene-keys.md has them, which
scene_keys_doc holds to the parser's key table: iteration_budget,
step_budget and the cuts' CUT_macro_step among them), and every option it
lists has a sentence of help. Usage: run_help_test.py BIN_DIR SOURCE_DIR"""

import os
import re
import subprocess
import sys

bin_dir, src = sys.argv[1], sys.argv[2]
doc = open(os.path.join(src, "docs", "scene-keys.md"), encoding="utf-8").read()
section = doc.split("## `[coupling]`", 1)[1].split("\n## ", 1)[0]
keys = re.findall(r"^\| `([a-z_]+)` \|", section, flags=re.M)
# The flag each key stands in for, as the key table's text gives it.
flags = {}
for k in keys:
    row = re.search(r"^\| `%s` \|.*$" % k, section, flags=re.M).group(0)
    found = re.findall(r"--[a-z-]+", row)
    flags[k] = found[0] if found else "--macro-step" if k.endswith("_macro_step") else None

out = subprocess.run([os.path.join(bin_dir, "master"), "run", "--help"], capture_output=True,
                     text=True, timeout=30)
text = out.stdout
failures = []
if out.returncode != 0 or "Usage:" not in text:
    failures.append("master run --help: exit %d: %s" % (out.returncode, out.stderr))
if len(keys) < 15:
    failures.append("only %d [coupling] keys read from docs/scene-keys.md: %s" % (len(keys), keys))
footer = text.split("[coupling]", 1)[-1] if "[coupling]" in text else ""
for k in keys:
    line = re.search(r"^\s*%s = (.*)$" % k, footer, flags=re.M)
    if line is None:
        failures.append("[coupling] %s is not in master run --help" % k)
    elif flags[k] and flags[k] not in line.group(1):
        failures.append("[coupling] %s: --help says %r, not its flag %s" % (k, line.group(0), flags[k]))
    elif k.endswith("_macro_step") and "%s=" % k[:2] not in line.group(1):
        failures.append("[coupling] %s: --help does not say --macro-step %s=H_cut" % (k, k[:2]))
# Every option has help: its entry holds more than the option and its type.
options = text.split("Options:", 1)[-1].split("\n\n", 1)[0]
for m in re.finditer(r"^  (-[^\n]*)\n((?:    [^\n]*\n)*)", options + "\n", flags=re.M):
    first = re.sub(r"^(\S+(?: \S+:\S+| \S+)?(?: REQUIRED)?)", "", m.group(1).strip())
    words = (first + " " + m.group(2)).split()
    if len(words) < 3:
        failures.append("option without help: %r" % m.group(1).strip())
for f in failures:
    print("FAIL " + f)
print("%d [coupling] keys checked against master run --help" % len(keys))
sys.exit(1 if failures else 0)
