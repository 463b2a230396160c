#!/usr/bin/env python3
"""Median [min-max] over the five runs of each run's paired speed ratio rtmini/Embree, CPU time
and wall time, per mesh and workload, with the issue's goal: the files of trav/ (trav_run.sh), or
with arguments FOLDER TAG those of FOLDER named *_TAG_run*.txt (ab_run.sh: ab static, ab dynamic); a third argument N keeps runs 1..N only."""
import glob, os, re, statistics, sys
here = os.path.dirname(os.path.abspath(__file__))
cpu_re = re.compile(r"paired CPU time .*speed ratio rtmini/embree median ([0-9.]+)")
wall_re = re.compile(r"paired \(5 repeats\): speed ratio rtmini/embree median ([0-9.]+)")
goal = {"ao_small": 1.0, "shadow": 1.0, "primary": 0.9, "diffuse": 0.9}
print("| mesh | workload | goal | CPU ratio median [min-max] | wall ratio median [min-max] | hash |")
print("|---|---|---|---|---|---|")
for m in ("dragon", "stanford-bunny"):
    for w in ("ao_small", "shadow", "primary", "diffuse"):
        cpu, wall, hashes = [], [], set()
        folder, tag = (sys.argv[1], "_" + sys.argv[2] if len(sys.argv) > 2 else "") if len(sys.argv) > 1 else ("trav", "")
        last = int(sys.argv[3]) if len(sys.argv) > 3 else 99
        paths = sorted(glob.glob(os.path.join(here, folder, f"{m}_{w}{tag}_run*.txt")))
        for path in [p for p in paths if int(re.search(r"_run(\d+)", p).group(1)) <= last]:
            text = open(path).read()
            cpu += [float(x) for x in cpu_re.findall(text)]
            wall += [float(x) for x in wall_re.findall(text)]
            hashes.update(re.findall(r"^FOM .* verification ([0-9a-f]{16})", text, re.M))
        f = lambda v: f"{statistics.median(v):.3f} [{min(v):.3f}-{max(v):.3f}]" if v else "-"
        print(f"| {m} | {w} | {goal[w]} | {f(cpu)} | {f(wall)} | {', '.join(sorted(hashes))} |")
