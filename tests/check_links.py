#!/usr/bin/python3
"""Every relative link of the README and the docs points at a file that exists and, when it
names a heading (`file.md#anchor`), at a heading of that file, with GitHub's anchors: lower
case, punctuation other than '-' and '_' dropped, each space a '-', repeats numbered -1, -2.

Usage (ctest runs it): check_links.py --source .
Prints each broken link and a last line `N passed, M failed` (one per file); exit status 1 if
any link is broken.
"""

import argparse
import glob
import os
import re
import sys

LINK = re.compile(r"(?<!\!)\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")


def anchors(path):
    """The anchors GitHub gives the headings of a markdown file (code blocks skipped)."""
    out, seen, fenced = set(), {}, False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line):
                fenced = not fenced
                continue
            m = None if fenced else HEADING.match(line)
            if not m:
                continue
            text = re.sub(r"`|\*\*|\*|\[([^\]]*)\]\([^)]*\)", r"\1", m.group(2)).lower()
            slug = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def links(path):
    """(line number, target) of every markdown link outside code blocks."""
    fenced = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if not fenced:
                for m in LINK.finditer(line):
                    yield number, m.group(1)


def broken(path, source):
    """The broken links of one file, as messages."""
    out = []
    for number, target in links(path):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto: ...
            continue
        file_part, _, anchor = target.partition("#")
        resolved = (os.path.normpath(os.path.join(os.path.dirname(path), file_part))
                    if file_part else path)
        where = f"{os.path.relpath(path, source)}:{number}: {target}"
        if not os.path.exists(resolved):
            out.append(f"{where}: no such file")
        elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
            out.append(f"{where}: no heading with that anchor")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", default=".", help="the source tree")
    source = os.path.abspath(parser.parse_args().source)
    files = [os.path.join(source, name) for name in ("README.md", "ARCHITECTURE.md",
                                                     "CHANGELOG.md")]
    files += sorted(glob.glob(os.path.join(source, "docs", "*.md")))
    files += [os.path.join(source, "reference", "schema.md")]
    failed = 0
    for path in files:
        problems = broken(path, source)
        for p in problems:
            print(f"FAILED  {p}")
        failed += bool(problems)
    print(f"{len(files) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
