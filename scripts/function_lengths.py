#!/usr/bin/env python3
"""Lines per function definition in C++ sources, longest first.

   scripts/function_lengths.py [--top N] DIR_OR_FILE...

A function is a brace block opened at namespace or class scope after a
parameter list; lambdas and local classes count toward the function that holds
them. Comments, strings and preprocessor lines are skipped first. Prints
"LINES FILE:FIRST-LAST NAME", one function per line.
"""
import os
import re
import sys

_TOKEN = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|'
                    r"'(?:\\.|[^'\\\n])*'|R\"([^(]*)\(.*?\)\1\"", re.S)


def _blank(m):
    return re.sub(r'[^\n]', ' ', m.group(0))


def strip(text):
    text = _TOKEN.sub(_blank, text)
    return re.sub(r'(?m)^[ \t]*#.*$', '', text)


def functions(path):
    with open(path, encoding='utf-8', errors='replace') as f:
        text = strip(f.read())
    stack = []  # (kind, start offset, name)
    head_start = 0
    out = []
    for i, ch in enumerate(text):
        if ch in ';':
            head_start = i + 1
        elif ch == '{':
            head = text[head_start:i]
            enclosing = stack[-1][0] if stack else 'namespace'
            kind = 'other'
            if enclosing in ('namespace', 'class'):
                if re.search(r'\bnamespace\b', head) or re.search(r'extern\s*$', head):
                    kind = 'namespace'
                elif re.search(r'\b(class|struct|union|enum)\b', head) and '(' not in head.split('{')[0].split(':')[0]:
                    kind = 'class'
                elif '(' in head and not re.search(r'=\s*$', head.strip()):
                    kind = 'function'
            name = ''
            if kind == 'function':
                m = re.search(r'([~\w:<>]+)\s*\(', head)
                name = m.group(1) if m else '?'
            stack.append((kind, i, name))
            head_start = i + 1
        elif ch == '}':
            if stack:
                kind, start, name = stack.pop()
                if kind == 'function':
                    first = text.count('\n', 0, start) + 1
                    last = text.count('\n', 0, i) + 1
                    out.append((last - first + 1, path, first, last, name))
            head_start = i + 1
    return out


def main(argv):
    top = 10
    if len(argv) > 1 and argv[0] == '--top':
        top, argv = int(argv[1]), argv[2:]
    found = []
    for root in argv:
        paths = [root] if os.path.isfile(root) else [
            os.path.join(d, f) for d, _, fs in os.walk(root) for f in fs
            if f.endswith(('.cpp', '.cc', '.h')) and 'third_party' not in d]
        for p in sorted(paths):
            found.extend(functions(p))
    found.sort(key=lambda r: (-r[0], r[1], r[2]))
    for n, p, a, b, name in found[:top]:
        print(f'{n} {p}:{a}-{b} {name}')


if __name__ == '__main__':
    main(sys.argv[1:])
