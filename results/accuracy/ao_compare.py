"""Per-vertex difference of two `bake --mode ao` .bin outputs (miniapps/bake/ao/README.md).

Usage: python3 ao_compare.py TEST.bin REFERENCE.bin
Prints one CSV row: vertices, RMS difference, mean difference (test - reference), largest
absolute difference, mean AO of the reference. AO values are visibility (1 = open).
"""
import struct
import sys

import numpy as np


def read_ao(path):
    with open(path, "rb") as f:
        data = f.read()
    instances, vertices = struct.unpack_from("<QQ", data, 0)
    start = 16 + 24 * instances
    if len(data) != start + 4 * vertices:
        sys.exit(f"{path}: size {len(data)} does not match {instances} instances, {vertices} vertices")
    return np.frombuffer(data, dtype="<f4", count=vertices, offset=start).astype(np.float64)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip().split("\n")[2])
    test, ref = read_ao(sys.argv[1]), read_ao(sys.argv[2])
    if test.shape != ref.shape:
        sys.exit(f"vertex counts differ: {test.size} vs {ref.size}")
    d = test - ref
    print(f"{ref.size},{np.sqrt(np.mean(d * d)):.5f},{np.mean(d):.5f},{np.max(np.abs(d)):.5f},"
          f"{np.mean(ref):.5f}")


if __name__ == "__main__":
    main()
