#!/usr/bin/env python3
"""Every relative link of every Markdown file of the repository leads somewhere.

The commands of the docs are checked by docs_commands_test.py; this test
checks their links. For each .md file of the source tree (build folders and
.git left out), outside code blocks and code spans, every inline link
`[text](target)`, image `![alt](target)` and reference definition
`[name]: target` whose target is relative (not http:, https:, mailto:)
must name a file or folder that exists, relative to the linking file; a
`#anchor` on a Markdown target (or alone, for the same file) must be the
slug of one of that file's headings, as GitHub makes it: the heading's
text without its markup, lower-cased, every character that is not a letter,
a digit, a space, '-' or '_' dropped, each space a '-'; a repeated heading
gets '-1', '-2', ... An explicit `<a id="...">` / `<a name="...">` counts too.

Usage: docs_links_test.py SOURCE_DIR  (exit 0 when every link resolves)
"""

import os
import re
import sys

SKIP_DIRS = {".git", "build", "node_modules", "__pycache__", ".ci"}
EXTERNAL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")  # http:, https:, mailto:, ...
# At least this many relative links are checked: a change that breaks the
# reading of the files fails here rather than checking nothing.
MIN_LINKS = 100


def markdown_files(source):
    for root, dirs, files in os.walk(source):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("build"))
        for f in sorted(files):
            if f.endswith(".md"):
                yield os.path.join(root, f)


def strip_code(text):
    """The text with fenced blocks and code spans blanked (lines kept)."""
    out, fence = [], None
    for line in text.split("\n"):
        m = re.match(r"^\s*(```+|~~~+)", line)
        if fence is None and m:
            fence = m.group(1)[0] * 3
            out.append("")
        elif fence is not None:
            if line.strip().startswith(fence):
                fence = None
            out.append("")
        else:
            out.append(re.sub(r"(`+)(.+?)\1", lambda c: " " * len(c.group(0)), line))
    return out


def heading_text(raw):
    """A heading's text as GitHub renders it: no markup, no trailing #s."""
    t = re.sub(r"\s+#+\s*$", "", raw.strip())
    t = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", t)  # links and images: their text
    t = re.sub(r"<[^>]+>", "", t)  # inline HTML
    t = t.replace("`", "")
    t = re.sub(r"(\*\*|__|\*|(?<!\w)_|_(?!\w))", "", t)  # emphasis markers
    return t


def slug(text):
    """GitHub's anchor of a heading's text."""
    s = heading_text(text).strip().lower()
    s = "".join(ch for ch in s if ch.isalnum() or ch in " -_")
    return s.replace(" ", "-")


def anchors(path, cache={}):
    """Every anchor a Markdown file offers: its headings' slugs (repeats
    numbered) and its explicit <a id/name>."""
    if path in cache:
        return cache[path]
    text = open(path, encoding="utf-8").read()
    found, seen = set(), {}
    fence = None
    for line in text.split("\n"):
        m = re.match(r"^\s*(```+|~~~+)", line)
        if m:
            fence = None if fence else m.group(1)[0]
            continue
        if fence:
            continue
        h = re.match(r"^ {0,3}#{1,6}\s+(.*)$", line)
        if h:
            base = slug(h.group(1))
            n = seen.get(base, 0)
            found.add(base if n == 0 else "%s-%d" % (base, n))
            seen[base] = n + 1
        for a in re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", line):
            found.add(a)
    cache[path] = found
    return found


LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFDEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$")


def links(path):
    """(line, target) of each link of the file outside code."""
    lines = strip_code(open(path, encoding="utf-8").read())
    text = "\n".join(lines)
    for m in LINK.finditer(text):  # a link's text may run over lines
        yield text.count("\n", 0, m.start()) + 1, m.group(1)
    for i, line in enumerate(lines, 1):
        m = REFDEF.match(line)
        if m:
            yield i, m.group(1)


def check(source, path, target):
    """A failure for one link, or None."""
    if EXTERNAL.match(target) or target.startswith("//"):
        return None
    file_part, _, anchor = target.partition("#")
    dest = path if not file_part else os.path.normpath(os.path.join(os.path.dirname(path), file_part))
    if file_part.startswith("/"):
        dest = os.path.join(source, file_part.lstrip("/"))
    if not os.path.exists(dest):
        return "%s does not exist" % os.path.relpath(dest, source)
    if anchor and dest.endswith(".md") and anchor not in anchors(dest):
        return "#%s is no heading of %s" % (anchor, os.path.relpath(dest, source))
    return None


# Headings of this repository's kind and the slugs GitHub's rule gives them.
SLUGS = {
    "The coupling in the scene: `[coupling]`": "the-coupling-in-the-scene-coupling",
    "Keys of the Green's-function soil": "keys-of-the-greens-function-soil",
    "Gauss–Seidel, **fast** and [linked](x.md) _here_": "gaussseidel-fast-and-linked-here",
    "4. Configure and Configured": "4-configure-and-configured",
    "snake_case names ##": "snake_case-names",
}


def main():
    source = os.path.abspath(sys.argv[1])
    failures, count = [], 0
    for text, want in SLUGS.items():
        if slug(text) != want:
            failures.append("slug(%r) is %r, GitHub makes %r" % (text, slug(text), want))
    for path in markdown_files(source):
        for line, target in links(path):
            if EXTERNAL.match(target):
                continue
            count += 1
            why = check(source, path, target)
            if why:
                failures.append("%s:%d: (%s) %s" % (os.path.relpath(path, source), line, target, why))
    print("%d relative links checked" % count)
    if count < MIN_LINKS:
        failures.append("only %d relative links found (at least %d expected): the reading of "
                        "the Markdown files is broken" % (count, MIN_LINKS))
    for f in failures:
        print("FAIL " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
