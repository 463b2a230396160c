#!/usr/bin/env python3
"""Tabulates the summaries written by run_distributed.sh (argument: its OUT_DIR): bake time
(base + map + iterate), speed-up and efficiency against the first run of each group, peak RSS
per rank (max, min), the map each rank holds, remote-read fraction and exchange bytes; then the
balance of each run: the phases, the slowest rank's mirror iteration against the mean (timings
.h5, when h5py is there) and the max / mean over ranks of the counted work (summary scene.work)."""
import glob
import json
import os
import sys

# Marks within iteration N come as "iteration N trace", "iteration N halo layout", "iteration N
# exchange plan" (the fused first iteration's halo and exchange plan), then "iteration N".
ITERATION_STEPS = ["trace", "halo layout", "exchange plan", ""]


def iteration_step(k):
    words = k.split()
    return int(words[1]), ITERATION_STEPS.index(" ".join(words[2:]))


def bake_time(phases):
    """The bake time of a summary's phases: base + map + halo + iterate (no read, set-up, write)."""
    return sum(phases.get(k, 0) for k in ("base", "map", "halo", "iterate"))


def rows(out, prefix):
    found = []
    for path in sorted(glob.glob(os.path.join(out, prefix + "_*.json"))):
        s = json.load(open(path))
        p = s["phases"]
        m = s["scene"].get("map", {})
        rss = s["scene"].get("peak_rss_bytes_per_rank", [s.get("peak_memory_bytes", 0)])
        base = s["scene"].get("scene_rss_bytes_per_rank", [0])
        found.append({
            "name": os.path.basename(path)[:-5], "ranks": s["ranks"], "threads": s["threads"],
            "time": bake_time(p),
            "vertices": s["scene"]["vertices"], "colors": s["scene"]["colors"],
            "rss_max": max(rss) / 2**30, "rss_min": min(rss) / 2**30,
            "scene_rss": max(base) / 2**30,
            "local": m.get("local_colors_max", 0), "remote": m.get("remote_read_fraction", 0),
            "bytes": m.get("exchange_bytes_per_iteration", 0), "hash": s["verification_hash"]})
    found.sort(key=lambda r: (r["ranks"] * r["threads"], r["ranks"]))
    return found


def table(title, found, weak):
    if not found:
        return
    print(f"\n### {title}\n")
    print("| run | ranks x threads | vertices | bake time (s) | speed-up | efficiency | peak RSS/rank "
          "max-min (GiB) | map/rank (% of whole) | remote reads | exchange MB/it | hash |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    t1 = found[0]["time"]
    for r in found:
        cores = r["ranks"] * r["threads"]
        speed = t1 / r["time"] if r["time"] > 0 else 0
        eff = speed if weak else speed / cores
        print(f"| {r['name']} | {r['ranks']} x {r['threads']} | {r['vertices']} | {r['time']:.3f} | "
              f"{'-' if weak else f'{speed:.2f}'} | {100 * eff:.0f} % | "
              f"{r['rss_max']:.3f}-{r['rss_min']:.3f} | {100 * r['local'] / r['colors']:.1f} | "
              f"{100 * r['remote']:.1f} % | {r['bytes'] / 1e6:.2f} | {r['hash']} |")


def balance(out, prefixes):
    """Per run: phases (max over ranks), slowest / mean rank of the mirror iterations that read the
    hit cache (iterations 2..K, median over them), and max / mean of the counted work."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        h5py = None
    print("\n### Balance: phases (s, max over ranks) and max / mean over ranks\n")
    print("| run | setup | map | halo | iterate | cached iteration slowest / mean (s) | "
          "trace nodes | iteration cost | lookups | items | remote reads | hits moved |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for prefix in prefixes:
        for path in sorted(glob.glob(os.path.join(out, prefix + "_*.json"))):
            s = json.load(open(path))
            name, p = os.path.basename(path)[:-5], s["phases"]
            w = s["scene"].get("work")
            if not w or s["ranks"] == 1:
                continue
            it = "-"
            h5 = path[:-5] + ".h5"
            if h5py is not None and os.path.exists(h5):
                t = h5py.File(h5, "r")["iterations/trace_time"][:]
                if t.shape[1] > 2:
                    per_rank = np.median(t[:, 2:], axis=1)
                    it = f"{per_rank.max():.3f} / {per_rank.mean():.3f} ({per_rank.max() / per_rank.mean():.2f}x)"
            ratio = lambda k: f"{w[k]['max_over_mean']:.3f}" if k in w else "-"
            moved = sum(w["moved_hits"]["per_rank"]) / max(1, sum(w["items"]["per_rank"]))
            print(f"| {name} | {p.get('setup', 0):.3f} | {p.get('map', 0):.3f} | {p.get('halo', 0):.3f} | "
                  f"{p.get('iterate', 0):.3f} | {it} | {ratio('trace_nodes')} | {ratio('iteration_cost')} | "
                  f"{ratio('lookups')} | {ratio('items')} | {ratio('remote_reads')} | {100 * moved:.1f} % |")


def cached_iterations(h5):
    """Per rank, the median of its mirror iterations that read the hit cache (2..K); None without
    h5py or the file."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return None
    if not os.path.exists(h5):
        return None
    t = h5py.File(h5, "r")["iterations/trace_time"][:]
    return np.median(t[:, 2:], axis=1) if t.shape[1] > 2 else None


def recut_table(out):
    """--balance measured against cost (recut_BALANCE_PxT_I, alternated): per configuration the
    median bake time and cached-iteration slowest / mean of each, and the recut's own figures
    (the first mirror iteration's measured max / mean, the cut's predicted max / mean after, the
    colours it moved, its bytes and seconds)."""
    runs = {}
    for path in glob.glob(os.path.join(out, "recut_*_*_*.json")):
        _, b, pt, _ = os.path.basename(path)[:-5].split("_")
        s = json.load(open(path))
        p = s["phases"]
        c = cached_iterations(path[:-5] + ".h5")
        runs.setdefault((pt, b), []).append({
            "time": p.get("base", 0) + p.get("map", 0) + p.get("halo", 0) + p.get("iterate", 0),
            "slow": c.max() / c.mean() if c is not None else float("nan"),
            "recut": s["scene"].get("recut"), "hash": s["verification_hash"]})
    if not runs:
        return
    med = lambda x: sorted(x)[len(x) // 2]
    print("\n### Measured recut against the counted cut (bunny_room N=300 K=4; alternated runs)\n")
    print("| ranks x threads | balance | runs | bake time median [min-max] (s) | cached iteration "
          "slowest / mean, median | first iteration max / mean | predicted after | colours moved | "
          "recut MB | recut s | hashes |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (pt, b) in sorted(runs, key=lambda k: (int(k[0].split("x")[0]), k[1])):
        r = runs[(pt, b)]
        t = [x["time"] for x in r]
        rc = [x["recut"] for x in r if x["recut"]]
        f = lambda k, scale=1.0, fmt="{:.3f}": fmt.format(med([x[k] * scale for x in rc])) if rc else "-"
        print(f"| {pt} | {b} | {len(r)} | {med(t):.3f} [{min(t):.3f}-{max(t):.3f}] | "
              f"{med([x['slow'] for x in r]):.3f} | {f('measured_max_over_mean')} | "
              f"{f('predicted_max_over_mean')} | {f('moved_fraction', 100, '{:.1f} %')} | "
              f"{f('bytes', 1e-6, '{:.2f}')} | {f('seconds')} | {' '.join(sorted(set(x['hash'] for x in r)))} |")


def busy_table(out, weak, weakspatial, prefix="busy", scene="the 1-rank scene", other="weakspatial"):
    """P concurrent 1-rank bakes of the 1-rank scene (PREFIX_P_i): the node as full as a P-rank run
    without communication. Their mean bake time is what a P-rank run's ranks would take if the
    distributed map cost nothing; weak_P against it is the distributed map's own efficiency."""
    groups = {}
    for path in glob.glob(os.path.join(out, prefix + "_*_*.json")):
        np_ = int(os.path.basename(path).split("_")[1])
        p = json.load(open(path))["phases"]
        groups.setdefault(np_, []).append(
            p.get("base", 0) + p.get("map", 0) + p.get("halo", 0) + p.get("iterate", 0))
    if not groups:
        return
    by_ranks = lambda found: {r["ranks"]: r["time"] for r in found}
    w, ws = by_ranks(weak), by_ranks(weakspatial)
    t1 = w.get(1, 0)
    print(f"\n### Weak scaling against the node as full without communication ({prefix}_P: "
          f"P concurrent 1 x 1 bakes of {scene})\n")
    print("| P | P concurrent 1 x 1: bake time mean / max (s) | vs weak_1 alone | weak_P (s) | "
          f"weak_P vs busy mean | {other}_P (s) | {other}_P vs busy mean |")
    print("|---|---|---|---|---|---|---|")
    for np_ in sorted(groups):
        t = groups[np_]
        mean, mx = sum(t) / len(t), max(t)
        eff = lambda d: f"{d[np_]:.3f} | {100 * mean / d[np_]:.0f} %" if np_ in d else "- | -"
        print(f"| {np_} | {mean:.3f} / {mx:.3f} ({len(t)} runs) | "
              f"{100 * t1 / mean if mean > 0 else 0:.0f} % | {eff(w)} | {eff(ws)} |")


def exchange_table(out):
    """Changed-only exchanges against full ones (exchange_EX_PxT_I, alternated): per configuration
    the median bake time, the median over runs of the cached exchanges' time (iterations 2..K-1,
    max over ranks, summed) and the bytes of each exchange (summed over ranks)."""
    try:
        import h5py
    except ImportError:
        h5py = None  # then only the bake times, hashes and the changed fraction
    runs = {}
    for path in glob.glob(os.path.join(out, "exchange_*_*_*.json")):
        _, ex, pt, _ = os.path.basename(path)[:-5].split("_")
        s = json.load(open(path))
        p = s["phases"]
        exchange, sent = float("nan"), "-"
        if h5py is not None and os.path.exists(path[:-5] + ".h5"):
            f = h5py.File(path[:-5] + ".h5", "r")
            t = f["iterations/allgather_time"][:]
            b = f["iterations/allgather_bytes"][:].sum(axis=0)
            exchange = float(t[:, 2:-1].max(axis=0).sum()) if t.shape[1] > 3 else float("nan")
            sent = " / ".join(f"{x / 1e6:.2f}" for x in b[1:-1])
        runs.setdefault((pt, ex), []).append({
            "time": p.get("base", 0) + p.get("map", 0) + p.get("halo", 0) + p.get("iterate", 0),
            "exchange": exchange, "bytes": sent, "hash": s["verification_hash"],
            "changed": s["scene"]["map"].get("exchange_changed_fraction", 1.0)})
    if not runs:
        return
    med = lambda x: sorted(x)[len(x) // 2]
    print("\n### Changed-only exchanges against full ones (bunny_room N=300 K=4; alternated)\n")
    print("| ranks x threads | exchange | runs | bake time median [min-max] (s) | cached exchanges' "
          "time, median (s) | MB per exchange | colours sent after the first | hashes |")
    print("|---|---|---|---|---|---|---|---|")
    for (pt, ex) in sorted(runs, key=lambda k: (int(k[0].split("x")[0]), k[1])):
        r = runs[(pt, ex)]
        t = [x["time"] for x in r]
        print(f"| {pt} | {ex} | {len(r)} | {med(t):.3f} [{min(t):.3f}-{max(t):.3f}] | "
              f"{med([x['exchange'] for x in r]):.4f} | {r[0]['bytes']} | "
              f"{100 * r[0]['changed']:.1f} % | {' '.join(sorted(set(x['hash'] for x in r)))} |")


def scaling_table(out):
    """Strong scaling in one run (scaling_1x1 once, scaling_PxT_I alternated): per shape the median
    bake time, its ratio to 1 x 16's median and the parallel efficiency against 1 x 1."""
    found = rows(out, "scaling")
    one = [r for r in found if r["name"] == "scaling_1x1"]
    runs = {}
    for r in found:
        if r["name"] != "scaling_1x1":
            runs.setdefault((r["ranks"], r["threads"]), []).append(r)
    if not one or not runs:
        return
    med = lambda x: sorted(x)[len(x) // 2]
    t1 = one[0]["time"]
    t16 = med([x["time"] for x in runs.get((1, 16), one)])
    print("\n### Strong scaling in one run (bunny_room N=300 K=4; 1 x 1 once, the rest alternated)\n")
    print("| ranks x threads | runs | bake time median [min-max] (s) | vs 1 x 16 | efficiency vs 1 x 1 "
          "| peak RSS/rank max (GiB) | bound 1.2/P x map + scene (GiB) | remote reads | exchange MB/it "
          "| hashes |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    # The memory bound: 1.2/P of the 1-rank figure's map part, plus the scene (the peak
    # before any map, measured per run: it is replicated and does not fall with P).
    map1 = one[0]["rss_max"] - one[0]["scene_rss"]
    bound = lambda r, p: f"{1.2 / p * map1 + r['scene_rss']:.3f}" if r["scene_rss"] > 0 else "-"
    print(f"| 1 x 1 | 1 | {t1:.3f} | - | 100 % | {one[0]['rss_max']:.3f} | {bound(one[0], 1)} | "
          f"0.0 % | 0.00 | {one[0]['hash']} |")
    for (p, t) in sorted(runs, key=lambda k: k[0]):
        r = runs[(p, t)]
        times = [x["time"] for x in r]
        m = med(times)
        print(f"| {p} x {t} | {len(r)} | {m:.3f} [{min(times):.3f}-{max(times):.3f}] | "
              f"{m / t16:.2f} | {100 * t1 / (p * t * m):.0f} % | {max(x['rss_max'] for x in r):.3f} | "
              f"{bound(max(r, key=lambda x: x['scene_rss']), p)} | "
              f"{100 * r[0]['remote']:.1f} % | "
              f"{r[0]['bytes'] / 1e6:.2f} | {' '.join(sorted(set(x['hash'] for x in r)))} |")


def memory_steps(out, prefix):
    """Per run, the rank with the highest peak RSS: its peak after each step of the run (summary
    scene.peak_rss_after_bytes_per_rank, newer summaries), the step that set it, and the halo."""
    found = []
    for path in sorted(glob.glob(os.path.join(out, prefix + "_*.json"))):
        s = json.load(open(path))
        steps = s["scene"].get("peak_rss_after_bytes_per_rank")
        if not steps:
            continue
        rss = s["scene"]["peak_rss_bytes_per_rank"]
        r = rss.index(max(rss))
        order = ["setup", "map", "halo"] + sorted(
            (k for k in steps if k.startswith("iteration")), key=iteration_step) + ["write"]
        after = [(k, steps[k][r] / 2**30) for k in order if k in steps]
        first = next(k for k, v in after if v >= max(rss) / 2**30 - 1e-9)
        found.append((os.path.basename(path)[:-5], s["ranks"], s["threads"], r, after, first,
                      s["scene"].get("map", {}).get("halo_colors_max", 0)))
    if not found:
        return
    found.sort(key=lambda f: (f[1] * f[2], f[1], f[0]))
    print("\n### Peak RSS after each step, rank with the highest peak (GiB)\n")
    names = [k for k, _ in found[0][4]]
    print("| run | rank | " + " | ".join(names) + " | peak set by | halo colours max |")
    print("|---|---|" + "---|" * len(names) + "---|---|")
    for name, _, _, r, after, first, halo in found:
        values = dict(after)
        print(f"| {name} | {r} | " + " | ".join(f"{values[k]:.3f}" if k in values else "-" for k in names)
              + f" | {first} | {halo:.0f} |")


def main(out):
    table("Strong scaling (bunny_room, N=300, K=4)", rows(out, "strong"), False)
    spatial = rows(out, "spatial")
    if spatial:
        strong = rows(out, "strong")
        table("Strong scaling, --balance spatial (speed-up against strong_1x1)", strong[:1] + spatial, False)
    pilot = rows(out, "pilot")
    if pilot:
        strong = rows(out, "strong")
        table("Strong scaling, --balance pilot (the cut before the recount; against strong_1x1)",
              strong[:1] + pilot, False)
    balance(out, ["strong", "scaling", "pilot", "spatial", "weak", "weakspatial", "weakmeasured", "weakrooms",
                  "weakroomssah", "weakshare", "weaksharesah"])
    weak = rows(out, "weak")
    table("Weak scaling (two sheets, side 150 sqrt(P), N=200, K=3)", weak, True)
    weakspatial = rows(out, "weakspatial")
    if weakspatial:
        table("Weak scaling, --balance spatial (efficiency against weak_1)", weak[:1] + weakspatial, True)
    weakmeasured = rows(out, "weakmeasured")
    if weakmeasured:
        table("Weak scaling, --balance measured (efficiency against weak_1)", weak[:1] + weakmeasured, True)
    busy_table(out, weak, weakspatial)
    recut_table(out)
    weakrooms = rows(out, "weakrooms")
    table("Weak scaling on closed rooms (P rooms, make_rooms_scene.py, N=200, K=3)", weakrooms, True)
    weakroomssah = rows(out, "weakroomssah")
    table("Weak scaling on closed rooms, --bvh sah", weakroomssah, True)
    weakshare = rows(out, "weakshare")
    table("Weak scaling on closed rooms, --node-sharing on", weakshare, True)
    table("Weak scaling on closed rooms, --node-sharing on --bvh sah", rows(out, "weaksharesah"), True)
    busy_table(out, weakrooms, weakshare, "busyrooms", "the 1-room scene", "weakshare")
    exchange_table(out)
    table("1M vertices, N=1000, K=2", rows(out, "big"), True)
    scaling_table(out)
    memory_steps(out, "scaling")


if __name__ == "__main__":
    main(sys.argv[1])
