#!/usr/bin/python3
"""Runs the commands of docs/getting-started.md and compares their output with the page.

Usage:
  /usr/bin/python3 scripts/check_getting_started.py FRICROM [DOC] [--print]

Every ```console block of DOC (default docs/getting-started.md) holds commands (lines "$ fricrom
...") each followed by the output it prints on stdout. The commands run from the repository root
with FRICROM for `fricrom`; `--out DIR` and `--to PATH` are redirected into a temporary folder.
Output is compared line by line after masking what changes from run to run: wall times
("0.35 s" -> "<t> s") and the file names after "wrote". A line "..." on the page stands for any
number of lines. --print shows each command's masked output instead of checking (to write the
page). Exit 1 on the first difference, naming the command and the line.
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
TIME = re.compile(r"\b\d+(?:\.\d+)?(?:e[-+]?\d+)? s\b")


def mask(line):
    line = TIME.sub("<t> s", line.rstrip())
    return re.sub(r"\bwrote .*", "wrote <files>", line)


def blocks(doc):
    """[(command, [expected lines])] of every ```console block, in order."""
    out, inside, current = [], False, None
    with open(doc, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if line.strip() == "```console":
                inside = True
                continue
            if inside and line.strip() == "```":
                inside, current = False, None
                continue
            if not inside:
                continue
            if line.startswith("$ "):
                cmd = line[2:]
                if not cmd.startswith("fricrom "):
                    raise SystemExit(f"{doc}:{n}: a command must start with 'fricrom ', got: {cmd}")
                current = (cmd, [], n)
                out.append(current)
            elif current is None:
                raise SystemExit(f"{doc}:{n}: output before any '$ fricrom' command")
            else:
                current[1].append(line)
    if not out:
        raise SystemExit(f"{doc}: no ```console block with a '$ fricrom' command")
    return out


def run(fricrom, cmd, tmp):
    args = shlex.split(cmd)[1:]
    def is_number(v):
        try:
            float(v)
            return True
        except ValueError:
            return False

    for i, a in enumerate(args[:-1]):  # `sweep --to 0.4` is a value, not a path
        v = args[i + 1]
        if a in ("--out", "--to") and not os.path.isabs(v) and not is_number(v):
            args[i + 1] = os.path.join(tmp, v)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    r = subprocess.run([fricrom] + args, cwd=ROOT, capture_output=True, text=True, env=env,
                       timeout=600)
    if r.returncode != 0:
        raise SystemExit(f"'{cmd}' exited with {r.returncode}:\n{r.stderr.strip()}")
    return [mask(line) for line in r.stdout.splitlines()]


def matches(expected, actual):
    """True when `actual` matches `expected`, where a line '...' stands for any lines."""
    if not expected:
        return not actual
    if expected[0] == "...":
        return any(matches(expected[1:], actual[k:]) for k in range(len(actual) + 1))
    return bool(actual) and mask(expected[0]) == actual[0] and matches(expected[1:], actual[1:])


def first_difference(expected, actual):
    for k, e in enumerate(expected):
        if e == "...":
            return f"page line {k + 1} onwards (after a '...') matches nothing in the output"
        if k >= len(actual):
            return f"page line {k + 1} '{e}': the output ended"
        if mask(e) != actual[k]:
            return f"page line {k + 1}:\n  page:   {mask(e)}\n  output: {actual[k]}"
    return f"the output goes on after the page's {len(expected)} lines: '{actual[len(expected)]}'"


def main(argv):
    args = [a for a in argv[1:] if a != "--print"]
    if not args or len(args) > 2:
        raise SystemExit(__doc__)
    fricrom = os.path.abspath(args[0])
    doc = args[1] if len(args) == 2 else os.path.join(ROOT, "docs", "getting-started.md")
    with tempfile.TemporaryDirectory() as tmp:
        for cmd, expected, n in blocks(doc):
            actual = run(fricrom, cmd, tmp)
            if "--print" in argv:
                print("$ " + cmd + "\n" + "\n".join(actual) + "\n")
                continue
            if not matches(expected, actual):
                print(f"{doc}:{n}: '{cmd}': {first_difference(expected, actual)}")
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
