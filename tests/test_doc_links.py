#!/usr/bin/python3
"""Every relative link of the README and the docs points at a file that exists and, when it
names a heading (`file.md#anchor`), at a heading of that file, with GitHub's anchors: lower
case, punctuation other than '-' and '_' dropped, each space a '-', repeats numbered -1, -2.

Usage (ctest runs it): python3 -m pytest tests/test_doc_links.py --source .
One case per file, its broken links in the failure.
"""

import glob
import os
import pathlib
import re

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


def documents(source):
    """The markdown files whose links are checked."""
    files = [os.path.join(source, name) for name in ("README.md", "ARCHITECTURE.md",
                                                     "CHANGELOG.md")]
    files += sorted(glob.glob(os.path.join(source, "docs", "*.md")))
    files += [os.path.join(source, "reference", "schema.md")]
    return files


def pytest_generate_tests(metafunc):
    # The cases are the files of --source, known only once the command line is read.
    if "document" in metafunc.fixturenames:
        source = str(pathlib.Path(metafunc.config.getoption("--source")).resolve())
        files = documents(source)
        metafunc.parametrize("document", files, ids=[os.path.relpath(f, source) for f in files])


def test_every_relative_link_reaches_its_target(document, source):
    problems = broken(document, str(source))
    assert not problems, "\n".join(problems)
