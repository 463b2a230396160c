#!/usr/bin/env python3
"""Writes a bake scene (.bs text) that grows with a parameter, for weak scaling of the
distributed map: a wavy mirror floor (Kr 0.5, N colours per vertex) facing a wavy diffuse
ceiling (one colour per vertex), lit by one emissive quad under the ceiling. Each sheet is a
SIDE x SIDE vertex grid over [-1, 1]^2 scaled by sqrt(SIDE), so the density of the geometry,
and with it the cost of a ray, stays the same as the scene grows. 2 * SIDE^2 + 4 vertices.

Usage: make_sheets_scene.py SIDE OUT.bs
"""
import math
import sys


def main():
    side = int(sys.argv[1])
    out = sys.argv[2]
    extent = 0.02 * side  # half-width: 0.04 between neighbouring vertices at any SIDE
    lines = []

    def grid(height, amplitude):
        for j in range(side):
            for i in range(side):
                x = -extent + 2 * extent * i / (side - 1)
                z = -extent + 2 * extent * j / (side - 1)
                y = height + amplitude * math.sin(3.1 * x) * math.cos(2.3 * z)
                lines.append(f"{x:.6f} {y:.6f} {z:.6f}")

    grid(0.0, 0.15)  # floor: vertices [0, side^2)
    grid(1.5, 0.10)  # ceiling: [side^2, 2 side^2)
    base = 2 * side * side
    for x, z in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)):
        lines.append(f"{x} 1.3 {z}")  # light quad, emitting downwards
    lines.append("")
    lines.append(": 0.3 0.3 0.3  0.5 0.5 0.5  0 0 0")  # 0: mirror floor
    lines.append(": 0.7 0.7 0.65  0 0 0  0 0 0")  # 1: diffuse ceiling
    lines.append(": 0.78 0.78 0.78  0 0 0  17 12 4")  # 2: light
    lines.append("")
    for sheet, material, flip in ((0, 0, False), (1, 1, True)):
        o = sheet * side * side
        for j in range(side - 1):
            for i in range(side - 1):
                a = o + j * side + i
                quad = [a, a + side, a + side + 1, a + 1]
                if flip:
                    quad.reverse()
                lines.append(f"{quad[0]} {quad[1]} {quad[2]} {quad[3]} {material}")
    lines.append(f"{base} {base + 1} {base + 2} {base + 3} 2")
    lines.append("!")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
