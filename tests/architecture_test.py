#!/usr/bin/env python3
"""The module picture of docs/architecture.md against the tree.

Checks (1) that the dependency table between the markers lists, for every
module folder, exactly the project libraries its CMakeLists.txt links, and
(2) that every top-level folder with a CMakeLists.txt is in the table and
every folder the modules table names exists, and (3) the same for the
modules inside master/: their table against the libraries
master/CMakeLists.txt builds and links, and against every #include line,
and (4) that every source and header in master/MODULE/ opens namespace
railcosim::MODULE and no other namespace block of railcosim's.
Exits non-zero naming each difference. Usage: architecture_test.py SOURCE_DIR
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
    # target_link_libraries(...), and the LINKS of master/'s module function
    for args in re.findall(r"target_link_libraries\(([^)]*)\)|\bLINKS\b([^)]*)\)", text):
        args = " ".join(args)
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

# Inside master/: the table of its modules against master/CMakeLists.txt (the
# modules each links, directly or through another) and against the includes
# of every file in each module's folder.
block = re.search(r"<!-- master modules: begin -->(.*?)<!-- master modules: end -->", doc, re.S)
if not block:
    sys.exit("docs/architecture.md: the master modules table's markers are missing")
inner = {}
for line in block.group(1).splitlines():
    m = re.match(r"\|\s*`(\w+)`\s*\|\s*(.*?)\s*\|$", line)
    if m:
        inner[m.group(1)] = set(re.findall(r"`(\w+)`", m.group(2)))
master_cmake = (root / "master" / "CMakeLists.txt").read_text()
direct = {}
for name, args in re.findall(r"railcosim_master_module\((\w+)(.*?)\)\n", master_cmake, re.S):
    links = re.search(r"\bLINKS\b(.*?)(?:\bPRIVATE_LINKS\b|$)", args, re.S)
    direct[name] = set(re.findall(r"railcosim_(\w+)", links.group(1) if links else ""))
def closure(name, seen=()):
    out = set()
    for dep in direct.get(name, ()):
        if dep in direct and dep not in seen:
            out |= {dep} | closure(dep, seen + (name,))
    return out
folders = sorted(d.name for d in (root / "master").iterdir() if d.is_dir())
for name in sorted(set(direct) | set(folders) | set(inner)):
    if name not in folders:
        problems.append(f"master module {name} has no folder master/{name}/")
        continue
    if name not in direct:
        problems.append(f"master/{name}/ is not a library in master/CMakeLists.txt")
        continue
    if name not in inner:
        problems.append(f"master/{name}/ is not in the master modules table")
        continue
    if closure(name) != inner[name]:
        problems.append(f"master/{name}/ links {sorted(closure(name)) or 'nothing'}, "
                        f"the table says {sorted(inner[name]) or 'nothing'}")
    for src in sorted((root / "master" / name).glob("*.?pp")):
        for inc in re.findall(r'^#include "(\w+)/[\w.]+"', src.read_text(), re.M):
            if inc in direct and inc != name and inc not in inner[name]:
                problems.append(f"master/{name}/{src.name} includes {inc}/, "
                                f"which master/{name}/ may not")
for src in sorted((root / "master").glob("*/*.?pp")):
    # Each module is a namespace named after its folder: its files open
    # railcosim::MODULE and no other block of railcosim's.
    want = f"railcosim::{src.parent.name}"
    opened = re.findall(r"^\s*namespace\s+(railcosim\b[\w:]*)\s*\{", src.read_text(), re.M)
    if want not in opened:
        problems.append(f"{src.relative_to(root)} does not open namespace {want}")
    for other in sorted(set(opened) - {want}):
        problems.append(f"{src.relative_to(root)} opens namespace {other}; "
                        f"a file of master/{src.parent.name}/ opens {want} only")
    for inc in re.findall(r'^#include "(\w+)\.hpp"', src.read_text(), re.M):
        if any((root / "master" / d / f"{inc}.hpp").exists() for d in folders):
            problems.append(f"{src.relative_to(root)} includes {inc}.hpp "
                            f"without its module's folder")

for p in problems:
    print("architecture:", p)
print(f"architecture: {len(modules)} modules and {len(folders)} master modules checked, "
      f"{len(problems)} differences")
sys.exit(1 if problems else 0)
