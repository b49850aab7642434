#!/usr/bin/env python3
"""Lists the functions of the production code (engine/, editor/; not tests, fuzz or generated
code) longer than a limit (150 lines by default), longest first: `scripts/long-functions.py [N]`.
A heuristic over braces (a function is an outermost `{ ... }` whose opening follows a
parameter list), good enough for this code base's style; lambdas count in their function."""
import pathlib
import re
import sys

LIMIT = int(sys.argv[1]) if len(sys.argv) > 1 else 150
ROOT = pathlib.Path(__file__).resolve().parent.parent
CONTROL = re.compile(r'^\s*(if|for|while|switch|catch|else|do)\b')
SIGNATURE = re.compile(r'\)\s*(const)?\s*(noexcept)?\s*(override)?\s*(->\s*[^{;]*)?\s*$')


def strip(line):
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])*'", "''", line)
    return line.split('//')[0]


def functions(path):
    lines = path.read_text(errors='replace').split('\n')
    depth, inside, start, head = 0, None, 0, ''
    for number, raw in enumerate(lines, 1):
        line = strip(raw)
        for i, ch in enumerate(line):
            if ch == '{':
                before = (head + ' ' + line[:i]).strip()
                if inside is None and SIGNATURE.search(before) and not CONTROL.match(before) \
                        and not re.search(r'\]\s*\(', before):
                    inside, start = depth, number
                    name = re.findall(r'([\w:~]+)\s*\(', before)
                    start_name = name[-1] if name else '?'
                depth += 1
                head = ''
            elif ch == '}':
                depth -= 1
                head = ''
                if inside is not None and depth == inside:
                    yield start_name, start, number - start + 1
                    inside = None
            elif ch == ';':
                head = ''
        head = (head + ' ' + line[line.rfind('}') + 1:] if '}' in line else head + ' ' + line)[-400:]


found = []
for folder in ('engine', 'editor'):
    for path in sorted((ROOT / folder).rglob('*')):
        if path.suffix in ('.cpp', '.h', '.hpp', '.c') and 'generated' not in path.parts:
            for name, line, length in functions(path):
                if length > LIMIT:
                    found.append((length, f'{path.relative_to(ROOT)}:{line}', name))
for length, where, name in sorted(found, reverse=True):
    print(f'{length:5d}  {where}  {name}')
sys.exit(1 if found else 0)
