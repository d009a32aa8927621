#!/usr/bin/python3
"""Checks that the README and the handbook (docs/*.md) describe the present, for users.

    scripts/check_docs.py [ROOT]

Fails (exit 1, one line per finding: file:line and what was found) on
- words of a development log: "session" (any use), "issue N", a commit hash ("abc1234 commit"
  or any bare 7-40 digit hex word with both digits and letters);
- a README of 200 lines or more;
- a relative link or image in a page whose target does not exist (pages the build generates,
  GENERATED below, may be absent in a source tree that has not generated them yet), or a link
  to a heading (#anchor) that the target page does not have (GitHub's heading slugs).
CHANGELOG.md, where the history lives, is not checked.
"""
import pathlib
import re
import sys

PATTERNS = [
    (re.compile(r"session [0-9]", re.I), "a development session"),
    (re.compile(r"\bsessions?\b", re.I), "the word 'session'"),
    (re.compile(r"\b[0-9a-f]{7,12}\b commit", re.I), "a commit hash"),
    (re.compile(r"issue [0-9]+", re.I), "an issue number"),
    (re.compile(r"(?<![\w.-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w.-])"),
     "a bare commit hash"),
]
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
GENERATED = {"docs/CASE_FILE.md", "docs/PYTHON_API.md"}
README_LINES = 200


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def anchors(path):
    """The page's heading anchors and its explicit <a id="..."> anchors."""
    out, seen, in_code = set(), {}, False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.lstrip().startswith("```"):
            in_code = not in_code
        if in_code:
            continue
        out.update(re.findall(r'<a id="([^"]+)"', line))
        if not line.startswith("#"):
            continue
        base = slug(line.lstrip("#"))
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def pages(root):
    out = [root / "README.md"] if (root / "README.md").exists() else []
    return out + sorted((root / "docs").glob("**/*.md"))


def check(root):
    findings = []
    for page in pages(root):
        rel = page.relative_to(root).as_posix()
        text = page.read_text(encoding="utf-8")
        in_code = False
        for number, line in enumerate(text.splitlines(), 1):
            for pattern, what in PATTERNS:
                match = pattern.search(line)
                if match:
                    findings.append(f"{rel}:{number}: {what}: '{match.group(0)}'")
            if line.lstrip().startswith("```"):
                in_code = not in_code
            if in_code:
                continue
            for target in LINK.findall(line):
                if re.match(r"[a-z]+:", target):
                    continue
                if target.startswith("#"):
                    if target[1:] not in anchors(page):
                        findings.append(f"{rel}:{number}: no heading '{target}' in this page")
                    continue
                file_part, _, anchor = target.partition("#")
                path = (page.parent / file_part).resolve()
                if path.exists():
                    if anchor and path.suffix == ".md" and anchor not in anchors(path):
                        findings.append(f"{rel}:{number}: no heading '#{anchor}' in {file_part}")
                    continue
                try:
                    generated = path.relative_to(root.resolve()).as_posix() in GENERATED
                except ValueError:
                    generated = False
                if not generated:
                    findings.append(f"{rel}:{number}: link to a missing file: '{target}'")
        if rel == "README.md" and len(text.splitlines()) >= README_LINES:
            findings.append(f"README.md: {len(text.splitlines())} lines (fewer than "
                            f"{README_LINES} wanted; the details belong in docs/)")
    return findings


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    findings = check(root)
    for f in findings:
        print(f)
    if findings:
        sys.exit(1)
    print(f"{len(pages(root))} pages clean")


if __name__ == "__main__":
    main()
