#!/usr/bin/python3
"""Prints fricrom's natural frequencies beside the paper's Table 3 (Zara et al. 2024)."""
import json
import sys

PAPER_FREE = [87.17, 87.17, 159.15, 159.15, 246.56, 246.56]
PAPER_STICK = [84.58, 84.58, 168.19, 168.19, 266.89, 266.89, 396.71, 396.71, 406.88, 406.88]


def main() -> int:
    if len(sys.argv) != 2:
        print("usage: compare_table3.py MODES.json (from `fricrom modes CASE --json`)", file=sys.stderr)
        return 2
    try:
        with open(sys.argv[1], encoding="utf-8") as f:
            data = json.load(f)
        free, stick = data["free_hz"], data["stick_hz"]
    except (OSError, ValueError, KeyError) as e:
        print(f"compare_table3.py: cannot read {sys.argv[1]}: {e}", file=sys.stderr)
        return 2
    print(f"{'mode':>4}  {'free':>9} {'paper':>8}  {'full-stick':>10} {'paper':>8}")
    worst = 0.0
    for i, (s, ps) in enumerate(zip(stick, PAPER_STICK)):
        row = f"{i + 1:>4}  "
        if i < len(free):
            row += f"{free[i]:9.2f} {PAPER_FREE[i]:8.2f}  "
            worst = max(worst, abs(free[i] - PAPER_FREE[i]))
        else:
            row += " " * 20
        row += f"{s:10.2f} {ps:8.2f}"
        worst = max(worst, abs(s - ps))
        print(row)
    ok = len(free) == 6 and len(stick) == 10 and worst <= 0.01
    print(f"largest difference from the paper: {worst:.4f} Hz ({'within' if ok else 'OUTSIDE'} 0.01 Hz)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
