#!/usr/bin/env python3
"""Lists the C++ functions longer than a limit, in lines from the first line
of the signature to the closing brace, longest first; exits 1 when any.
A brace-matching scan, not a parser: comments, strings and preprocessor
lines are blanked, then a function is a '{' at namespace or class scope
whose preceding text ends in ')' (with qualifiers, a trailing return type
or a constructor's initialisers). Usage: function_lengths.py LIMIT FILE...
"""
import re, sys, pathlib
limit = int(sys.argv[1]); out = []
for path in sys.argv[2:]:
    text = pathlib.Path(path).read_text()
    # blank out comments and strings, keep newlines
    text = re.sub(r'//[^\n]*', '', text)
    text = re.sub(r'/\*.*?\*/', lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text, flags=re.S)
    text = re.sub(r'R"(\w*)\((.*?)\)\1"', lambda m: '""' + '\n' * m.group(0).count('\n'), text, flags=re.S)
    text = re.sub(r'"(\\.|[^"\\\n])*"', '""', text)
    text = re.sub(r"'(\\.|[^'\\\n])*'", "''", text)
    text = re.sub(r'^[ \t]*#[^\n]*', '', text, flags=re.M)
    stack = []  # (kind, start_line, name)
    last = 0
    line = 1
    for i, c in enumerate(text):
        if c == '\n': line += 1
        elif c == '{':
            head = text[last:i]
            last = i + 1
            scope_ok = all(k in ('ns', 'class') for k, _, _ in stack)
            h = ' '.join(head.split())
            kind = 'block'
            if re.match(r'^(export\s+)?(inline\s+)?namespace\b', h) or h.startswith('extern "'): kind = 'ns'
            elif re.search(r'\b(class|struct|union|enum)\b[^()]*$', h): kind = 'class'
            elif scope_ok and re.search(r'\)\s*(const|noexcept|override|final|->[^{]*|\s)*$', h) or (scope_ok and re.search(r'\)\s*:\s*[\w:<>]+[({]', h)):
                kind = 'fn'
            elif scope_ok and re.search(r'\)\s*:', h): kind = 'fn'
            start = line - head.lstrip().count('\n')
            m = re.search(r'([\w:~]+)\s*\(', h)
            stack.append((kind, start, m.group(1) if m else '?'))
        elif c == '}':
            last = i + 1
            if stack:
                kind, start, name = stack.pop()
                if kind == 'fn' and line - start + 1 > limit:
                    out.append((line - start + 1, f'{path}:{start}', name))
        elif c == ';':
            last = i + 1
for n, where, name in sorted(out, reverse=True):
    print(f'{n:4d} {where} {name}')
print(f'{len(out)} functions over {limit} lines in {len(sys.argv) - 2} files', file=sys.stderr)
sys.exit(1 if out else 0)
