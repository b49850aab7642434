#!/usr/bin/env python3
"""Counts the skipped tests in ctest's JUnit report and fails where a test that must run in this
configuration skipped: `scripts/check-skips.py REPORT.xml [--must-run REGEX]...` (ctest
--output-junit REPORT.xml). Prints `skipped: N of M` and each skipped test with its reason;
exit 1 when a skipped test's name matches one of the --must-run patterns (for example
'^EditorWindow\\.' in the full build, '^blender_addon$' where Blender is installed)."""
import argparse
import re
import sys
import xml.etree.ElementTree as ElementTree

parser = argparse.ArgumentParser()
parser.add_argument('report')
parser.add_argument('--must-run', action='append', default=[], metavar='REGEX')
args = parser.parse_args()

cases = ElementTree.parse(args.report).getroot().iter('testcase')
total, skipped = 0, []
for case in cases:
    total += 1
    status = case.get('status', '')
    mark = case.find('skipped')
    if status in ('notrun', 'skipped', 'disabled') or mark is not None:
        reason = (mark.get('message', '') if mark is not None else '') or status
        output = case.findtext('system-out') or ''
        found = re.search(r'Skipped\s*\n?(.*)', output)
        skipped.append((case.get('name', '?'), (found.group(1).strip() if found else reason)[:160]))
print(f'skipped: {len(skipped)} of {total}')
bad = []
for name, reason in skipped:
    required = any(re.search(p, name) for p in args.must_run)
    print(f'  {"MUST RUN " if required else ""}{name}: {reason}')
    if required:
        bad.append(name)
if bad:
    print(f'check-skips: {len(bad)} test(s) that must run in this configuration skipped', file=sys.stderr)
    sys.exit(1)
