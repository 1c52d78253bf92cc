#!/usr/bin/env python3
"""The size targets of docs/architecture.md, measured.

Lists the C++ functions longer than LIMIT lines (from the first line of the
signature to the closing brace), longest first, and with --max-file-lines N
the files longer than N lines; exits 1 when there is any.

A brace-matching scan, not a parser: comments, strings and preprocessor
lines are blanked, then a function is a '{' at namespace or class scope
whose preceding text ends in ')' (with qualifiers, a trailing return type
or a constructor's initialisers); lambdas count as part of their function.

Usage: function_lengths.py LIMIT [--max-file-lines N] FILE...
"""
import pathlib
import re
import sys


def blank(text):
    """The text with comments, literals and preprocessor lines blanked (lines kept)."""
    keep_lines = lambda m: re.sub(r"[^\n]", " ", m.group(0))
    text = re.sub(r'R"(\w*)\((.*?)\)\1"', lambda m: '""' + "\n" * m.group(0).count("\n"), text,
                  flags=re.S)
    text = re.sub(r'"(\\.|[^"\\\n])*"', '""', text)
    text = re.sub(r"'(\\.|[^'\\\n])*'", "''", text)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", keep_lines, text, flags=re.S)
    return re.sub(r"^[ \t]*#[^\n]*", "", text, flags=re.M)


def kind_of(head, at_scope):
    """What a '{' opens, from the text before it."""
    h = " ".join(head.split())
    if re.match(r"^(export\s+)?(inline\s+)?namespace\b", h) or h.startswith('extern ""'):
        return "ns"
    if re.search(r"\b(class|struct|union|enum)\b[^()]*$", h):
        return "class"
    if at_scope and (re.search(r"\)\s*(const|noexcept|override|final|->[^{]*|\s)*$", h)
                     or re.search(r"\)\s*:", h)):
        return "fn"
    return "block"


def long_functions(path, limit):
    """(lines, 'path:line', name) of every function of `path` over `limit` lines."""
    text = blank(pathlib.Path(path).read_text())
    found, stack, last, line = [], [], 0, 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            head, last = text[last:i], i + 1
            kind = kind_of(head, all(k in ("ns", "class") for k, _, _ in stack))
            name = re.search(r"([\w:~]+)\s*\(", head)
            stack.append((kind, line - head.lstrip().count("\n"), name.group(1) if name else "?"))
        elif c == "}":
            last = i + 1
            if stack:
                kind, start, name = stack.pop()
                if kind == "fn" and line - start + 1 > limit:
                    found.append((line - start + 1, f"{path}:{start}", name))
        elif c == ";":
            last = i + 1
    return found


def main(argv):
    limit, files, max_file = int(argv[0]), argv[1:], None
    if files[:1] == ["--max-file-lines"]:
        max_file, files = int(files[1]), files[2:]
    functions = sorted((f for p in files for f in long_functions(p, limit)), reverse=True)
    for n, where, name in functions:
        print(f"{n:4d} {where} {name}")
    big = []
    if max_file is not None:
        big = [(len(pathlib.Path(p).read_text().splitlines()), p) for p in files]
        big = sorted((b for b in big if b[0] > max_file), reverse=True)
        for n, p in big:
            print(f"{n:4d} {p} (file)")
    print(f"{len(functions)} functions over {limit} lines"
          + (f", {len(big)} files over {max_file} lines" if max_file is not None else "")
          + f" in {len(files)} files", file=sys.stderr)
    return 1 if functions or big else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
