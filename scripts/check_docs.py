#!/usr/bin/python3
"""Checks that the user docs describe the software as it is, and that every figure has its script.

Usage:
  /usr/bin/python3 scripts/check_docs.py [REPO]      exit 1 naming file and line of each finding

Rules (docs/ without docs/decisions/, README.md, benchmarks/README.md, include/fricrom/):
  1. the word "session" does not occur (the history lives in git and docs/decisions/);
  2. a date (YYYY-MM-DD) stands only beside a measured number: on its line or table row, or on
     the two lines before or after it in the same paragraph;
  3. every image `![..](path)` exists, and one of the two lines below it names the script that
     regenerates it (`scripts/NAME.py` or `scripts/NAME.sh`, a file that exists).
Figures under docs/figures/ that no page shows are listed too: a figure nobody reads is stale.
"""
import glob
import os
import re
import sys

DATE = re.compile(r"\b20\d\d-\d\d-\d\d\b")
# A measured number: a value with a unit or a ratio, e.g. "36.1 s", "0.752", "+9.8 %", "1.5e-4 m".
MEASURED = re.compile(
    r"\d(?:[.,]\d+)?(?:[eE·][−\-+]?\d+|·10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?\s?"
    r"(?:s|ms|µs|us|ns|min|h|Hz|m|mm|N|kN|J|Pa|MiB|GiB|MB|GB|%|×|x|1/s|points|pts|runs)\b"
    r"|\b\d+\.\d+\b")
IMAGE = re.compile(r"!\[[^\]]*\]\(([^)\s]+)\)")
SCRIPT = re.compile(r"scripts/([A-Za-z0-9_\-]+\.(?:py|sh))")
SESSION = re.compile(r"\bsessions?\b", re.IGNORECASE)


def checked_files(repo):
    files = [p for p in glob.glob(os.path.join(repo, "docs", "*.md"))]
    files += [os.path.join(repo, "README.md"), os.path.join(repo, "benchmarks", "README.md")]
    files += glob.glob(os.path.join(repo, "include", "fricrom", "*.h"))
    return sorted(f for f in files if os.path.isfile(f))


def check_file(repo, path, shown):
    findings = []
    rel = os.path.relpath(path, repo)
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for i, line in enumerate(lines):
        where = f"{rel}:{i + 1}"
        if SESSION.search(line):
            findings.append(f"{where}: mentions a session: {line.strip()[:100]}")
        for date in DATE.finditer(line):
            # Beside: on its line, or on the two lines before or after it in the same paragraph
            # (a date that closes or introduces a sentence or a table of measurements).
            rest = line[:date.start()] + line[date.end():]
            for step in (1, -1):
                for j in range(i + step, i + 3 * step, step):
                    if j < 0 or j >= len(lines) or not lines[j].strip():
                        break
                    rest += " " + lines[j]
            if not MEASURED.search(rest):
                findings.append(f"{where}: date {date.group(0)} beside no measured number")
        for image in IMAGE.finditer(line):
            target = os.path.normpath(os.path.join(os.path.dirname(path), image.group(1)))
            shown.add(target)
            if not os.path.isfile(target):
                findings.append(f"{where}: image {image.group(1)} does not exist")
            below = " ".join(lines[i + 1:i + 3])
            scripts = SCRIPT.findall(below)
            if not scripts:
                findings.append(f"{where}: image {image.group(1)} names no script "
                                "(scripts/NAME.py|sh) in the two lines below it")
            for name in scripts:
                if not os.path.isfile(os.path.join(repo, "scripts", name)):
                    findings.append(f"{where}: image {image.group(1)}: scripts/{name} missing")
    return findings


def main():
    repo = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(__file__), ".."))
    shown = set()
    findings = []
    for path in checked_files(repo):
        findings += check_file(repo, path, shown)
    for figure in sorted(glob.glob(os.path.join(repo, "docs", "figures", "*.png"))):
        if os.path.normpath(figure) not in shown:
            findings.append(f"{os.path.relpath(figure, repo)}: shown on no page")
    for finding in findings:
        print(finding)
    if findings:
        print(f"check_docs.py: {len(findings)} finding(s)", file=sys.stderr)
        return 1
    print("check_docs.py: docs clean (no session, dates beside measurements, figures scripted)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
