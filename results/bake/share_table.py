#!/usr/bin/python3
"""Table of a node-sharing call (results/bake/raw_16core_share/callN): bake time per
configuration, median [min-max] over its rounds, the ratio of the medians to 1 x 16's, and with
the runs' summaries (runs.tgz) the largest rank's peak RSS and PSS and the node's PSS summed.

Usage: share_table.py CALL_DIR  (prints markdown)"""
import json
import re
import statistics
import sys
import tarfile
from collections import defaultdict
from pathlib import Path

call = Path(sys.argv[1])
times = defaultdict(list)
hashes = set()
for line in (call / "times.txt").read_text().splitlines():
    m = re.match(r"(\S+?)(?:_(\d+))? bake time ([0-9.]+) s verification ([0-9a-f]+)", line)
    if m:
        times[m.group(1)].append(float(m.group(3)))
        hashes.add(m.group(4))

# config -> (peak RSS, max PSS) of the largest rank, the ranks' max PSS summed, MiB
memory = defaultdict(lambda: ([], [], []))
if (call / "runs.tgz").exists():
    with tarfile.open(call / "runs.tgz") as tar:
        for member in tar.getmembers():
            m = re.match(r"runs/(\S+?)(?:_(\d+))?\.json$", member.name)
            if not m:
                continue
            scene = json.load(tar.extractfile(member))["scene"]
            rss, pss, node = memory[m.group(1)]
            rss.append(max(scene["peak_rss_bytes_per_rank"]) / 2**20)
            if "max_pss_after_step_bytes_per_rank" in scene:
                pss.append(max(scene["max_pss_after_step_bytes_per_rank"]) / 2**20)
                node.append(sum(scene["max_pss_after_step_bytes_per_rank"]) / 2**20)


def order(name):
    k8 = name.startswith("k8_")
    m = re.search(r"(\d+)x(\d+)", name)
    return (k8, -int(m.group(2)) if m else 0, int(m.group(1)) if m else 0, "off" not in name, "scene" not in name,
            "work" not in name)


ref = {False: statistics.median(times.get("r1x16", [float("nan")])),
       True: statistics.median(times.get("k8_1x16", [float("nan")]))}
print("| run | K | ranks x threads | node sharing | bake time (s), median [min-max] | n | / 1 x 16 "
      "| peak RSS, largest rank (MiB) | max PSS, largest rank (MiB) | PSS summed (MiB) |")
print("|---|---|---|---|---|---|---|---|---|---|")
for name in sorted(times, key=order):
    t = times[name]
    k8 = name.startswith("k8_")
    shape = re.search(r"(\d+x\d+)", name).group(1).replace("x", " x ")
    # --node-sharing off, scene, work or on (calls 1-5: off or on)
    sharing = next((v for v in ("on", "off", "scene", "work") if f"_{v}" in name), "-")
    rss, pss, node = memory.get(name, ([], [], []))
    mem = lambda v: f"{statistics.median(v):.1f}" if v else "-"
    print(f"| {name} | {8 if k8 else 4} | {shape} | {sharing} | {statistics.median(t):.3f} "
          f"[{min(t):.3f}-{max(t):.3f}] | {len(t)} | {statistics.median(t) / ref[k8]:.3f} | "
          f"{mem(rss)} | {mem(pss)} | {mem(node)} |")
print(f"\nverification hashes: {', '.join(sorted(hashes))}")
