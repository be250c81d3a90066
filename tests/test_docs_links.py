"""The documentation stands on its own (pytest, run by CTest as docs_links).

Every relative link and image in README.md and docs/**/*.md must name a file inside the
repository, and a link with a #anchor must name a heading of that file (GitHub's anchors:
lower case, punctuation dropped, spaces to hyphens, -1, -2, ... for repeated headings). No
document may send the reader outside the repository: no mention of spec/ or ../shared.

    /usr/bin/python3 -m pytest tests/test_docs_links.py      (TSUBU_SOURCE_DIR: the repository)
"""
import os
import re
import unicodedata
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("TSUBU_SOURCE_DIR", Path(__file__).resolve().parent.parent)).resolve()
DOCS = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])

FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
OUTSIDE = re.compile(r"(?<![\w.-])spec/|\.\./shared|/work/shared")


def prose_lines(path):
    """(line number, text) of the lines outside fenced code blocks."""
    inside = False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield number, line


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link keeps its text
    text = text.strip().lower()
    kept = "".join(c for c in text if c in " -_" or unicodedata.category(c)[0] in "LN")
    return kept.replace(" ", "-")


def anchors(path):
    """The headings' anchors and explicit HTML anchors (<a id="name"></a>)."""
    seen, found = {}, set()
    for _, line in prose_lines(path):
        found.update(re.findall(r'<a\s+(?:id|name)="([^"]+)"', line))
        m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        base = slug(m.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        found.add(base if n == 0 else f"{base}-{n}")
    return found


def links(path):
    for number, line in prose_lines(path):
        for m in LINK.finditer(CODE_SPAN.sub("", line)):
            yield number, m.group(1)


def problems(path):
    out = []
    for number, target in links(path):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # https:, mailto:, ...
            continue
        file_part, _, anchor = target.partition("#")
        where = f"{path.relative_to(ROOT)}:{number}: {target}"
        dest = (path.parent / file_part).resolve() if file_part else path
        if ROOT != dest and ROOT not in dest.parents:
            out.append(f"{where}: leaves the repository")
        elif not dest.exists():
            out.append(f"{where}: no such file")
        elif anchor:
            if dest.suffix != ".md":
                out.append(f"{where}: an anchor into a file that is not Markdown")
            elif anchor not in anchors(dest):
                out.append(f"{where}: no heading '#{anchor}' in {dest.relative_to(ROOT)}")
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if OUTSIDE.search(line):
            out.append(f"{path.relative_to(ROOT)}:{number}: points outside the repository: {line.strip()}")
    return out


@pytest.mark.parametrize("path", DOCS, ids=lambda p: str(p.relative_to(ROOT)))
def test_links_and_anchors_resolve_inside_the_repository(path):
    assert problems(path) == []


def test_the_checker_finds_what_it_must(tmp_path):
    """A broken file, a broken anchor, a link out of the tree and a spec/ mention are caught;
    a good anchor and a link inside code are not."""
    global ROOT
    root, ROOT = ROOT, tmp_path
    try:
        (tmp_path / "docs").mkdir()
        (tmp_path / "a.md").write_text("# Top\n\n## A `key` (and more)\n\n## A `key` (and more)\n")
        doc = tmp_path / "docs" / "b.md"
        doc.write_text(
            "[ok](../a.md#a-key-and-more) [ok2](../a.md#a-key-and-more-1) [self](#here)\n\n# Here\n\n"
            "[gone](missing.md) [bad](../a.md#nope) [out](../../x.md) see spec/x.md\n\n"
            "`[code](nowhere.md)`\n\n```\n[block](nowhere.md)\n```\n"
        )
        found = problems(doc)
        assert len(found) == 4, found
        assert "missing.md: no such file" in found[0]
        assert "no heading '#nope'" in found[1]
        assert "leaves the repository" in found[2]
        assert "points outside the repository" in found[3]
    finally:
        ROOT = root
