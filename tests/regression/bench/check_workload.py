#!/usr/bin/env python3
"""regression.bench.workload_file: the file of rtmini-bvh-bench --write-workload holds what a
peer needs (bench/workload_file.hpp): its size matches its counts, and every sampled ray's
answer, recomputed here by brute force over all triangles (Moller-Trumbore in float64), is the
one the bench recorded. Rays whose nearest hit lies within a relative 1e-5 of tmax or of a
triangle's edge may go either way and are not counted against it.

Usage: check_workload.py FILE [SAMPLE]
"""
import sys

import numpy as np


def read(path):
    data = open(path, "rb").read()
    assert data[:8] == b"RTMWORK1", f"{path}: bad magic {data[:8]!r}"
    any_hit, reserved = np.frombuffer(data, np.uint32, 2, 8)
    nt, nr = (int(x) for x in np.frombuffer(data, np.uint64, 2, 16))
    want = 32 + nt * 36 + nr * 36
    assert len(data) == want, f"{path}: {len(data)} bytes, counts say {want}"
    assert reserved == 0
    off = 32
    tris = np.frombuffer(data, np.float32, nt * 9, off).reshape(nt, 3, 3).astype(np.float64)
    off += nt * 36
    rays = np.frombuffer(data, np.float32, nr * 8, off).reshape(nr, 8).astype(np.float64)
    off += nr * 32
    answers = np.frombuffer(data, np.int32, nr, off)
    return bool(any_hit), tris, rays, answers


def nearest(tris, ray):
    """(t, triangle, margin) of the nearest hit in (tmin, tmax), or (inf, -1, margin)."""
    o, d, tmin, tmax = ray[0:3], ray[3:6], ray[6], ray[7]
    a, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-300
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = o - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    inside = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > tmin) & (t < tmax)
    # Distance of each candidate from the decision's boundaries (barycentric edges, the segment's
    # ends), for the rays a float traversal may fairly decide the other way.
    edge = np.minimum(np.minimum(np.abs(u), np.abs(v)), np.abs(1 - u - v))
    near_edge = ok & (edge < 1e-5) & (t > tmin - 1e-5 * tmax) & (t < tmax * (1 + 1e-5))
    near_end = ok & (u >= -1e-5) & (v >= -1e-5) & (u + v <= 1 + 1e-5) & \
        (np.abs(t - tmax) < 1e-5 * max(1.0, abs(tmax)))
    ambiguous = bool(np.any(near_edge | near_end))
    if not inside.any():
        return np.inf, -1, ambiguous
    k = int(np.argmin(np.where(inside, t, np.inf)))
    return t[k], k, ambiguous


def main():
    path = sys.argv[1]
    sample = int(sys.argv[2]) if len(sys.argv) > 2 else 500
    any_hit, tris, rays, answers = read(path)
    assert len(rays) > 0 and len(tris) > 0
    rng = np.random.default_rng(7)
    picks = rng.choice(len(rays), size=min(sample, len(rays)), replace=False)
    wrong = ambiguous_count = hits = 0
    for i in picks:
        t, k, ambiguous = nearest(tris, rays[i])
        expect = int(k >= 0) if any_hit else k
        hits += k >= 0
        if expect != answers[i]:
            if ambiguous:
                ambiguous_count += 1
            else:
                wrong += 1
                print(f"ray {i}: file says {answers[i]}, brute force {expect} (t {t})")
    print(f"{path}: {'any' if any_hit else 'closest'} hit, {len(tris)} triangles, {len(rays)} "
          f"rays; {len(picks)} sampled, {hits} hit, {wrong} wrong, {ambiguous_count} differ "
          f"within 1e-5 of an edge or of tmax")
    # The sample must exercise more than one answer, else agreement proves little.
    if any_hit:
        assert 0 < hits < len(picks), "the sample has only hits or only misses"
    else:
        assert len(set(answers[picks])) >= 10, "the sample hits fewer than 10 triangles"
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
