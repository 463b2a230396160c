#!/usr/bin/env python3
"""ETA over time from a --progress log (stderr of sketchtrace or bake run with --progress
into a file): for each progress line, the shown ETA, the true remaining time (the final
line's elapsed minus this line's), and the linear-in-items ETA the old code printed
(elapsed * (100 - percent) / percent), as a Markdown table.

The line prints the ETA in whole seconds, so near the end of a run the rounding alone makes a
large relative error (1.6 s left shows as 0:00:02, +25 %). The "beyond rounding" figure counts
only what is off by more than the half second the display cannot show:
max(0, |ETA - truth| - 0.5) / truth, with the sign of the error.

Usage: eta_table.py LOG [LOG...]
"""
import re
import sys

LINE = re.compile(r"\]\s+([\d.]+)%.*?([\d.]+) s elapsed\s+(ETA (\d+):(\d\d):(\d\d)|ETA \?|done)")


def rows(path):
    out = []
    for line in open(path):
        m = LINE.search(line)
        if not m:
            continue
        pct, t = float(m.group(1)), float(m.group(2))
        eta = None if m.group(4) is None else int(m.group(4)) * 3600 + int(m.group(5)) * 60 + int(m.group(6))
        out.append((pct, t, eta, m.group(3) == "done"))
    return out


def table(path):
    r = rows(path)
    total = [t for pct, t, eta, done in r if done][-1]
    print(f"\n{path}: {total:.1f} s of progress-line time\n")
    print("| elapsed s | work by time % | items % | true remaining s | ETA s | ETA error | "
          "beyond rounding | linear ETA s | linear error |")
    print("|---|---|---|---|---|---|---|---|---|")
    worst_after_10 = worst_lin_after_10 = worst_rounded_after_10 = 0.0
    for pct, t, eta, done in r:
        if done or eta is None or pct <= 0:
            continue
        truth = total - t
        if truth <= 0.5:
            continue
        lin = t * (100 - pct) / pct
        err, lerr = eta / truth - 1, lin / truth - 1
        rounded = max(0.0, abs(eta - truth) - 0.5) / truth * (1 if eta >= truth else -1)
        share = t / total
        if share >= 0.10:
            worst_after_10 = max(worst_after_10, abs(err))
            worst_rounded_after_10 = max(worst_rounded_after_10, abs(rounded))
            worst_lin_after_10 = max(worst_lin_after_10, abs(lerr))
        print(f"| {t:.1f} | {100 * share:.0f} | {pct:.1f} | {truth:.1f} | {eta} | {100 * err:+.0f} % | "
              f"{100 * rounded:+.0f} % | {lin:.1f} | {100 * lerr:+.0f} % |")
    print(f"\nworst |error| once >= 10 % of the time has passed: ETA {100 * worst_after_10:.0f} % "
          f"({100 * worst_rounded_after_10:.0f} % beyond the display's rounding), "
          f"linear {100 * worst_lin_after_10:.0f} %")


for p in sys.argv[1:]:
    table(p)
