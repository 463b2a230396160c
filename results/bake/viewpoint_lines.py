#!/usr/bin/env python3
"""How many 64-byte cache lines one viewpoint lookup touches in a vertex's block of N colours
(12 bytes each), with the colours stored in Fibonacci index order (as the map stores them) or in
bake's coherent order (chef.cpp's coherent_order: about sqrt(N / 2) latitude bands, each walked
in longitude, alternating). A lookup reads the 8 viewpoints nearest to a direction (the k-d
tree's neighbours within the Fibonacci radius hold up to that many); directions are uniform on
the sphere, the block's start at a random 4-byte offset within a line. Usage:
viewpoint_lines.py [N ...] (default 200 300 1000)."""
import sys

import numpy as np

GOLDEN = (1 + 5 ** 0.5) / 2


def fibonacci_points(n):
    i = np.arange(n)
    z = 1 - (2 * i + 1) / n
    phi = 2 * np.pi * ((i / GOLDEN) % 1.0)
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], 1)


def coherent_positions(points):
    """Position of each viewpoint in coherent order (the inverse of coherent_order)."""
    n = len(points)
    bands = max(1, round((n / 2) ** 0.5))
    key = []
    for i, p in enumerate(points):
        band = min(bands - 1, int((1 - p[2]) * 0.5 * bands))
        phi = np.arctan2(p[1], p[0])
        key.append((band * 10 + (phi if band % 2 == 0 else -phi) / 4, i))
    key.sort()
    pos = np.empty(n, int)
    for k, (_, i) in enumerate(key):
        pos[i] = k
    return pos


def mean_lines(points, pos, rng, lookups=4000):
    q = rng.normal(size=(lookups, 3))
    q /= np.linalg.norm(q, axis=1)[:, None]
    counts = []
    for d in q:
        nearest = np.argsort(-points @ d)[:8]
        first = rng.integers(0, 16) * 4 + pos[nearest] * 12
        lines = set((first // 64).tolist()) | set(((first + 11) // 64).tolist())
        counts.append(len(lines))
    return float(np.mean(counts))


def main():
    rng = np.random.default_rng(1)
    print("| N | lines per lookup, Fibonacci order | coherent order |")
    print("|---|---|---|")
    for n in [int(a) for a in sys.argv[1:]] or [200, 300, 1000]:
        p = fibonacci_points(n)
        fib = mean_lines(p, np.arange(n), rng)
        coh = mean_lines(p, coherent_positions(p), rng)
        print(f"| {n} | {fib:.2f} | {coh:.2f} |")


if __name__ == "__main__":
    main()
