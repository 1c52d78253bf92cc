#!/usr/bin/env python3
"""The module picture of docs/architecture.md against the tree.

Checks (1) that the dependency table between the markers lists, for every
module folder, exactly the project libraries its CMakeLists.txt links, and
(2) that every top-level folder with a CMakeLists.txt is in the table and
every folder the modules table names exists. Exits non-zero naming each
difference. Usage: architecture_test.py SOURCE_DIR
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
doc = (root / "docs" / "architecture.md").read_text()
block = re.search(r"<!-- dependencies: begin -->(.*?)<!-- dependencies: end -->", doc, re.S)
if not block:
    sys.exit("docs/architecture.md: the dependency table's markers are missing")

documented = {}
for line in block.group(1).splitlines():
    m = re.match(r"\|\s*`(\w+)`\s*\|\s*(.*?)\s*\|$", line)
    if m:
        documented[m.group(1)] = set(re.findall(r"`(\w+)`", m.group(2)))

# The library each folder defines, so links can be named by folder.
library_of = {}
for cm in root.glob("*/CMakeLists.txt"):
    for lib in re.findall(r"add_library\((railcosim_\w+)", cm.read_text()):
        if lib != "railcosim_proto":  # the generated code, part of protocol/
            library_of[lib] = cm.parent.name

problems = []
modules = sorted(cm.parent.name for cm in root.glob("*/CMakeLists.txt")
                 if cm.parent.name not in ("tests", "bench"))
for module in modules:
    text = (root / module / "CMakeLists.txt").read_text()
    linked = set()
    for args in re.findall(r"target_link_libraries\(([^)]*)\)", text):
        for lib in re.findall(r"\b(railcosim_\w+)", args):
            if lib in library_of and library_of[lib] != module:
                linked.add(library_of[lib])
    if module not in documented:
        problems.append(f"{module}/ is not in the dependency table")
    elif documented[module] != linked:
        problems.append(f"{module}/ links {sorted(linked) or 'nothing'}, "
                        f"the table says {sorted(documented[module]) or 'nothing'}")
for module in documented:
    if module not in modules:
        problems.append(f"the table names {module}/, which has no CMakeLists.txt")
for folder in re.findall(r"^\| `([\w/]+)/`", doc, re.M):
    if not (root / folder).is_dir():
        problems.append(f"the modules table names {folder}/, which does not exist")

for p in problems:
    print("architecture:", p)
print(f"architecture: {len(modules)} modules checked, {len(problems)} differences")
sys.exit(1 if problems else 0)
