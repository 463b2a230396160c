#!/usr/bin/env python3
"""Max and mean |a - b| over the per-vertex AO of two `bake ao` .bin outputs of one scene
(layout: miniapps/bake/ao/README.md), and how many vertices differ at all. Standard library only.
Usage: bin_diff.py A.bin B.bin"""
import array, struct, sys


def values(path):
    data = open(path, "rb").read()
    receivers, vertices = struct.unpack_from("<QQ", data, 0)
    start = 16 + 24 * receivers
    out = array.array("f")
    out.frombytes(data[start:start + 4 * vertices])
    if sys.byteorder != "little":
        out.byteswap()
    return out


a, b = values(sys.argv[1]), values(sys.argv[2])
assert len(a) == len(b), "different vertex counts"
d = [abs(float(x) - float(y)) for x, y in zip(a, b)]
print(f"vertices {len(d)}, max |diff| {max(d):.3g}, mean {sum(d) / len(d):.3g}, "
      f"differing {sum(1 for x in d if x != 0)}")
