#!/usr/bin/env python3
"""docs/scene-keys.md against `master keys --markdown`: the committed
reference of the scene keys is what the parser's key table prints.

Usage: scene_keys_doc_test.py BIN_DIR SOURCE_DIR
"""
import difflib
import pathlib
import re
import subprocess
import sys


def keys(bin_dir: pathlib.Path, *flags: str) -> str:
    return subprocess.run([str(bin_dir / "master"), "keys", *flags], check=True,
                          capture_output=True, text=True, timeout=30).stdout


def text_matches_markdown(text: str, markdown: str) -> bool:
    """The text reference has the Markdown's tables and, in each, its keys."""
    # "[table]", or "[[table.key]]" for the entries of an array of tables.
    header = r"\[\[?[\w.]+\]\]?"
    tables = re.findall(rf"^## `({header})`$", markdown, re.M)
    sections = dict(re.findall(rf"^({header})\n((?:  .*\n?)*)", text, re.M))
    ok = bool(tables) and list(sections) == tables
    for table in tables:
        part = markdown.split(f"## `{table}`")[1].split("\n## ")[0]
        for key in re.findall(r"^\| `([^`]+)` \|", part, re.M):
            if not re.search(rf"^  {re.escape(key)}: ", sections.get(table, ""), re.M):
                print(f"master keys: {table} {key} is missing from the text reference")
                ok = False
    return ok


def main() -> int:
    bin_dir, source = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    printed = keys(bin_dir, "--markdown")
    if not text_matches_markdown(keys(bin_dir), printed):
        print("master keys and master keys --markdown list different tables or keys")
        return 1
    doc = source / "docs" / "scene-keys.md"
    committed = doc.read_text(encoding="utf-8") if doc.exists() else ""
    if printed == committed:
        print(f"docs/scene-keys.md matches `master keys --markdown` ({printed.count(chr(10))} lines)")
        return 0
    diff = list(difflib.unified_diff(committed.splitlines(), printed.splitlines(),
                                     "docs/scene-keys.md (committed)",
                                     "master keys --markdown", lineterm="", n=1))
    print("\n".join(diff[:40]))
    if len(diff) > 40:
        print(f"... {len(diff) - 40} more diff lines")
    print("docs/scene-keys.md is stale: regenerate it with\n"
          "  build/bin/master keys --markdown > docs/scene-keys.md\n"
          "and commit it with the change to the key table.", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
