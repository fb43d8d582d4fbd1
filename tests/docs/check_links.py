#!/usr/bin/env python3
"""Check the relative links of Markdown pages: every link or image to a file
of the tree must name an existing file or directory, and a link with a
#fragment must name a heading of the page it points to (the anchors a forge
makes: GitHub's rule, lower case, punctuation dropped, blanks to '-', a
repeated heading numbered -1, -2, ...). External links (http:, https:,
mailto:) are not followed. Code spans and fenced code blocks are skipped.

Also: a fenced block with the info string `nml` preceded by the comment
`<!-- deck: PATH -->` must equal the file PATH (relative to the page), so
that a deck shown in a page is the deck that make test checks and runs.

usage: check_links.py FILE.md ...
Prints one `ok` or `FAIL` line per page and "suite links: N passed, N failed";
exits 1 on a failure.
"""
import os
import re
import sys

RE_FENCE = re.compile(r"^\s*(```|~~~)(.*)$")
RE_LINK = re.compile(r"(!?)\[((?:[^\[\]]|\[[^\]]*\])*)\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
RE_REF_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*(\S+)")
RE_HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
RE_HTML_ANCHOR = re.compile(r"<a\s+(?:name|id)=\"([^\"]+)\"")
RE_DECK_MARK = re.compile(r"<!--\s*deck:\s*(\S+)\s*-->")


def slug(text):
    """GitHub's anchor of a heading text."""
    t = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)     # links: their text
    t = t.replace("`", "")
    t = re.sub(r"<[^>]+>", "", t)                            # inline html
    t = t.strip().lower()
    t = re.sub(r"[^\w\- ]", "", t)                           # \w keeps letters, digits, _
    return t.replace(" ", "-")


def parse(path):
    """Headings' anchors, links (line, target) and nml blocks of a page."""
    anchors, links, decks = {}, [], []
    counts = {}
    in_fence, fence, info, block, mark, pending_mark = False, "", "", [], None, None
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for no, line in enumerate(lines, 1):
        m = RE_FENCE.match(line)
        if in_fence:
            if m and m.group(1) == fence and not m.group(2).strip():
                if info == "nml":
                    decks.append((start, mark, "\n".join(block)))
                in_fence = False
            else:
                block.append(line)
            continue
        if m:
            in_fence, fence, info, block, start = True, m.group(1), m.group(2).strip(), [], no
            mark, pending_mark = pending_mark, None
            continue
        dm = RE_DECK_MARK.search(line)
        if dm:
            pending_mark = dm.group(1)
        elif line.strip():
            pending_mark = None
        for a in RE_HTML_ANCHOR.findall(line):
            anchors[a] = no
        h = RE_HEADING.match(line)
        if h:
            s = slug(h.group(2))
            k = counts.get(s, 0)
            counts[s] = k + 1
            anchors[s if k == 0 else f"{s}-{k}"] = no
        code_free = re.sub(r"`[^`]*`", "", line)
        for m in RE_LINK.finditer(code_free):
            links.append((no, m.group(3)))
        r = RE_REF_DEF.match(code_free)
        if r:
            links.append((no, r.group(1)))
    return anchors, links, decks


def main(argv):
    pages = argv[1:]
    if not pages:
        print(__doc__)
        return 2
    cache = {}

    def anchors_of(p):
        if p not in cache:
            cache[p] = parse(p)[0]
        return cache[p]

    passed = failed = 0
    for page in pages:
        problems = []
        _, links, decks = parse(page)
        base = os.path.dirname(page)
        n = 0
        for no, target in links:
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):   # http:, https:, mailto:
                continue
            n += 1
            path, _, frag = target.partition("#")
            dest = os.path.normpath(os.path.join(base, path)) if path else page
            if not os.path.exists(dest):
                problems.append(f"line {no}: '{target}': no file {dest}")
                continue
            if frag:
                if not dest.endswith(".md") or os.path.isdir(dest):
                    problems.append(f"line {no}: '{target}': an anchor into a file that is not a page")
                elif frag not in anchors_of(dest):
                    problems.append(f"line {no}: '{target}': no heading with anchor #{frag} in {dest}")
        for start, mark, text in decks:
            if mark is None:
                continue
            dest = os.path.normpath(os.path.join(base, mark))
            try:
                with open(dest, encoding="utf-8") as f:
                    want = f.read().rstrip("\n")
            except OSError:
                problems.append(f"line {start}: deck block of '{mark}': no file {dest}")
                continue
            if text.rstrip("\n") != want:
                problems.append(f"line {start}: the deck block differs from {dest} (copy the file into the page)")
        if problems:
            failed += 1
            print(f"  FAIL  {page}: " + "; ".join(problems))
        else:
            passed += 1
            print(f"  ok    {page}: {n} relative links" + (f", {sum(1 for d in decks if d[1])} deck blocks"
                                                            if any(d[1] for d in decks) else ""))
    print(f"suite links: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
