#!/usr/bin/env python3
"""ETA over time from a --progress log (stderr of sketchtrace or bake run with --progress
into a file): for each progress line, the shown ETA, the true remaining time (the final
line's elapsed minus this line's), and the linear-in-items ETA the old code printed
(elapsed * (100 - percent) / percent), as a Markdown table.

The line prints the ETA in whole seconds, so near the end of a run the rounding alone makes a
large relative error (1.6 s left shows as 0:00:02, +25 %). The "beyond rounding" figure counts
only what is off by more than the half second the display cannot show:
max(0, |ETA - truth| - 0.5) / truth, with the sign of the error.

--cpu (a log written by cpu_clock.py, every line stamped with the process's CPU seconds):
the same comparison on the process's CPU clock, which other people's load on a shared machine
does not move. The line's ETA is read as its estimate of the work left over the work done
(ETA / elapsed), applied to the CPU seconds used since the line started; the truth is the
CPU seconds still to be used. That error is the estimator's own.

--label L: only the progress lines of label L (bake ao prints "bake ao rays" and
"bake ao mapping" lines into one log).

Usage: eta_table.py [--cpu] [--label L] LOG [LOG...]
"""
import argparse
import bisect
import re

LINE = re.compile(r"^(?:@ ([\d.]+) ([\d.]+) )?(.*?): \[.*\]\s+([\d.]+)%.*?([\d.]+) s elapsed\s+"
                  r"(ETA (\d+):(\d\d):(\d\d)|ETA \?|done)")
STAMP = re.compile(r"^@ ([\d.]+) ([\d.]+)")


def read(path, label):
    """Progress lines (percent, elapsed, eta or None, done, wall, cpu) and the clock samples."""
    lines, samples = [], []
    for text in open(path):
        s = STAMP.match(text)
        if s:
            samples.append((float(s.group(1)), float(s.group(2))))
        m = LINE.search(text)
        if not m or (label and m.group(3).strip() != label):
            continue
        eta = None if m.group(7) is None else int(m.group(7)) * 3600 + int(m.group(8)) * 60 + int(m.group(9))
        wall = float(m.group(1)) if m.group(1) else None
        cpu = float(m.group(2)) if m.group(2) else None
        lines.append((float(m.group(4)), float(m.group(5)), eta, m.group(6) == "done", wall, cpu))
    return lines, samples


def cpu_at(samples, wall):
    """The process's CPU seconds at `wall`, interpolated between the samples around it."""
    walls = [w for w, _ in samples]
    k = bisect.bisect_left(walls, wall)
    if k <= 0:
        return samples[0][1]
    if k >= len(samples):
        return samples[-1][1]
    (w0, c0), (w1, c1) = samples[k - 1], samples[k]
    return c0 + (c1 - c0) * (wall - w0) / (w1 - w0) if w1 > w0 else c1


def signed_beyond(estimate, truth, half):
    """How far `truth` lies outside [estimate - half, estimate + half], over truth, signed."""
    off = max(0.0, abs(estimate - truth) - half)
    return off / truth * (1 if estimate >= truth else -1)


def table(path, label, cpu):
    lines, samples = read(path, label)
    final = [r for r in lines if r[3]][-1]
    total = final[1]
    what = f" ({label})" if label else ""
    clock = ("CPU clock of the process (the other columns: the line's wall-clock figures)"
             if cpu else "wall clock")
    print(f"\n{path}{what}: {total:.1f} s of progress-line time, errors on the {clock}\n")
    print("| elapsed s | work by time % | items % | true remaining s | ETA s | ETA error | "
          "beyond rounding | linear ETA s | linear error |")
    print("|---|---|---|---|---|---|---|---|---|")
    if cpu:
        start_cpu = cpu_at(samples, final[4] - final[1])  # the line's clock started here
        end_cpu = final[5]
    worst = worst_rounded = worst_linear = 0.0
    for pct, t, eta, done, wall, used in lines:
        if done or eta is None or pct <= 0 or t <= 0:
            continue
        truth = total - t
        if truth <= 0.5:
            continue
        linear = t * (100 - pct) / pct
        err, rounded, lerr = eta / truth - 1, signed_beyond(eta, truth, 0.5), linear / truth - 1
        if cpu:  # the same estimates as ratios of work left to work done, on the CPU clock
            spent, left = used - start_cpu, end_cpu - used
            if spent <= 0 or left <= 0:
                continue
            err = spent * eta / t / left - 1
            rounded = signed_beyond(spent * eta / t, left, spent * 0.5 / t)
            lerr = spent * (100 - pct) / pct / left - 1
        share = t / total
        if share >= 0.10:
            worst = max(worst, abs(err))
            worst_rounded = max(worst_rounded, abs(rounded))
            worst_linear = max(worst_linear, abs(lerr))
        print(f"| {t:.1f} | {100 * share:.0f} | {pct:.1f} | {truth:.1f} | {eta} | {100 * err:+.0f} % | "
              f"{100 * rounded:+.0f} % | {linear:.1f} | {100 * lerr:+.0f} % |")
    print(f"\nworst |error| once >= 10 % of the time has passed: ETA {100 * worst:.0f} % "
          f"({100 * worst_rounded:.0f} % beyond the display's rounding), "
          f"linear {100 * worst_linear:.0f} %")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cpu", action="store_true", help="errors on the process's CPU clock")
    parser.add_argument("--label", default="", help="only the progress lines of this label")
    parser.add_argument("logs", nargs="+")
    args = parser.parse_args()
    for path in args.logs:
        table(path, args.label, args.cpu)


if __name__ == "__main__":
    main()
