#!/usr/bin/env python3
"""check-docs.py - the documentation's references resolve inside the repository.

    python3 scripts/check-docs.py [ROOT]

Checks every file git tracks (and untracked files that git does not ignore):
  * a reference `docs/NAME.md "Section"` (in code comments, docs and scripts; the quoted text may
    wrap onto the next line) names a file in docs/ with a heading that contains Section;
  * a reference to docs/NAME.md names a file that exists;
  * every document named bare in prose (NAME.md) is a file of the repository (a note that lives
    elsewhere is not), and no relative path climbs out of the repository.
Prints each problem as FILE:LINE: what, and exits 1 when there is any.
"""
import os
import re
import subprocess
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..')
git = ['git', '-C', root, 'ls-files']
files = subprocess.run(git, capture_output=True, text=True).stdout.split()
files += subprocess.run(git + ['--others', '--exclude-standard'], capture_output=True, text=True).stdout.split()
SELF = 'scripts/check-docs.py'
# A document named bare in prose (a path with a folder, or a name in a code string, is a file the
# code writes or a docs/ reference checked below).
ANY_MD = re.compile(r'(?<![\w./$\'"-])()([A-Za-z0-9_-]+\.md)\b')
CLIMB = re.compile(r'(?<![\w./])((?:\.\./)+)[A-Za-z0-9_]')
md_names = {os.path.basename(f) for f in files if f.endswith('.md')}
REF = re.compile(r'docs/([a-z0-9-]+\.md),?[ \t]*(?:\n[ \t]*(?:\*|#|//)?[ \t]*)?["\u201c]([^"\u201d\n]+(?:\n[ \t]*(?:\*|#|//)?[ \t]*[^"\u201d\n]+)?)["\u201d]')
MENTION = re.compile(r'docs/([a-z0-9-]+\.md)')

headings = {}


def doc_headings(name):
    if name not in headings:
        path = os.path.join(root, 'docs', name)
        headings[name] = None if not os.path.exists(path) else [
            line.lstrip('#').strip().lower() for line in open(path, encoding='utf-8') if line.startswith('#')]
    return headings[name]


problems = 0
for f in sorted(set(files)):
    path = os.path.join(root, f)
    if f == SELF or f.startswith('fuzz/corpus/') or not os.path.isfile(path):
        continue
    try:
        text = open(path, encoding='utf-8').read()
    except (UnicodeDecodeError, OSError):
        continue
    def report(pos, what):
        global problems
        problems += 1
        print(f'{f}:{text.count(chr(10), 0, pos) + 1}: {what}')
    for m in ANY_MD.finditer(text):
        if m.group(2) not in md_names:
            report(m.start(), f'cites a document the repository does not hold: {m.group(0)}')
    for m in CLIMB.finditer(text):
        depth = m.group(1).count('../')
        if depth > f.count('/'):
            report(m.start(), f'a path that leaves the repository: {m.group(0)}')
    for m in MENTION.finditer(text):
        if doc_headings(m.group(1)) is None:
            report(m.start(), f'no such file: docs/{m.group(1)}')
    for m in REF.finditer(text):
        name = m.group(1)
        section = re.sub(r'\s*\n\s*(?:\*|#|//)?\s*', ' ', m.group(2)).strip()
        found = doc_headings(name)
        if found is None or re.search(r'[$;{}=]', section):
            continue
        if not any(section.lower() in h for h in found):
            report(m.start(), f'docs/{name} has no heading "{section}"')
sys.exit(1 if problems else 0)
