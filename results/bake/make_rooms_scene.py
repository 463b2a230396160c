#!/usr/bin/env python3
"""Writes a bake scene (.bs text) of ROOMS identical closed rooms side by side (a building, about
sqrt(ROOMS) x sqrt(ROOMS) rooms), for weak scaling of the distributed map: the work per room is
the same at any ROOMS, and no ray leaves its room, so a rank that owns whole rooms does the
same work at any rank count (only the BVH grows, by its depth). Each room: a gently curved
mirror floor (Kr 0.5, N colours per vertex, like make_sheets_scene.py's floor), two facing
mirror-ish walls (Kr 0.3), two diffuse walls, a diffuse ceiling with a square skylight, and a
mirror-ish sphere floating above the floor; every surface a SIDE-wide grid of 0.06 between
vertices (walls SIDE/2 high). The skylights open onto one emissive quad just above every ceiling,
which the walls reach through, so each room stays closed.

Why one light for the whole building: bake's direct light loops over every emissive face for every
vertex (chef.cpp's DirectLight), so a lamp per room would make every vertex's shadow rays grow
with ROOMS. One quad keeps them constant (its samples that fall above another room end on this
room's ceiling: the same number of rays, noisier light).

Vertices are written room by room (rows of rooms along x, then z), each room's surfaces in turn:
the default ownership cut (contiguous vertex ranges of equal cost) then gives each rank whole
rooms when the ranks divide the rooms. 2 SIDE^2 + 4 SIDE (SIDE // 2 + 3) + 1,106 vertices a
room (the ceiling's vertices inside the skylight belong to no face: one colour each, never read).

Usage: make_rooms_scene.py ROOMS OUT.bs [SIDE]   (SIDE default 100: 42,306 vertices a room)
"""
import math
import sys

SPACING = 0.06  # between neighbouring vertices, as the sheets scene's 0.04 keeps density fixed
GAP = 0.3  # between neighbouring rooms (the walls' backs face it)


def main():
    rooms = int(sys.argv[1])
    out = sys.argv[2]
    side = int(sys.argv[3]) if len(sys.argv) > 3 else 100
    width = SPACING * (side - 1)  # inside of a room: [0, width]^2 in x and z
    height = width / 2
    high = side // 2 + 1  # wall vertices up a wall
    cols = math.ceil(math.sqrt(rooms))
    pitch = width + GAP
    positions, faces = [], []

    def patch(origin, du, dv, nu, nv, lift=None, skip=None, material=0):
        """A nu x nv vertex grid origin + i du + j dv (+ lift(u, v) along du x dv), quads facing
        du x dv; skip(i, j) leaves quad (i, j) out."""
        first = len(positions)
        n = [du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
             du[0] * dv[1] - du[1] * dv[0]]
        norm = math.sqrt(sum(c * c for c in n))
        n = [c / norm for c in n]
        for j in range(nv):
            for i in range(nu):
                h = lift(i / (nu - 1), j / (nv - 1)) if lift else 0.0
                positions.append([origin[k] + i * du[k] + j * dv[k] + h * n[k] for k in range(3)])
        for j in range(nv - 1):
            for i in range(nu - 1):
                if skip and skip(i, j):
                    continue
                a = first + j * nu + i
                faces.append((a, a + 1, a + nu + 1, a + nu, material))

    def sphere(centre, radius, slices, stacks, material):
        """Latitude-longitude sphere, outward faces: rings of `slices` vertices, then the poles."""
        first = len(positions)
        for j in range(1, stacks):
            theta = math.pi * j / stacks
            for i in range(slices):
                phi = 2 * math.pi * i / slices
                positions.append([centre[0] + radius * math.sin(theta) * math.cos(phi),
                                  centre[1] + radius * math.cos(theta),
                                  centre[2] + radius * math.sin(theta) * math.sin(phi)])
        top, bottom = len(positions), len(positions) + 1
        positions.append([centre[0], centre[1] + radius, centre[2]])
        positions.append([centre[0], centre[1] - radius, centre[2]])
        ring = lambda j, i: first + (j - 1) * slices + i % slices
        for i in range(slices):
            faces.append((top, ring(1, i + 1), ring(1, i), material))
            faces.append((bottom, ring(stacks - 1, i), ring(stacks - 1, i + 1), material))
            for j in range(1, stacks - 1):
                faces.append((ring(j, i), ring(j, i + 1), ring(j + 1, i + 1), ring(j + 1, i),
                              material))

    w, s = width, SPACING
    below, above = -0.1, height + 0.1  # walls reach past the floor's dip and the light
    wall_rows = high + 2  # wall grid rows between `below` and `above`
    ws = (above - below) / (wall_rows - 1)
    hole = lambda i, j: all(0.35 * (side - 1) <= k < 0.65 * (side - 1) for k in (i, j))
    # Floor dips up to 0.08 in the middle, flat at the walls (no gap where they meet).
    dip = lambda u, v: -0.08 * math.sin(math.pi * u) * math.sin(math.pi * v) * (
        1 + 0.5 * math.cos(7.0 * u) * math.sin(5.0 * v))
    for r in range(rooms):
        x0, z0 = (r % cols) * pitch, (r // cols) * pitch
        # floor, facing +y: du along z, dv along x
        patch((x0, 0.0, z0), (0, 0, s), (s, 0, 0), side, side, lift=dip, material=0)
        # ceiling with its skylight, facing -y
        patch((x0, height, z0), (s, 0, 0), (0, 0, s), side, side, skip=hole, material=1)
        # mirror-ish walls at x = 0 (facing +x) and x = w (facing -x)
        patch((x0, below, z0), (0, ws, 0), (0, 0, s), wall_rows, side, material=2)
        patch((x0 + w, below, z0), (0, 0, s), (0, ws, 0), side, wall_rows, material=2)
        # diffuse walls at z = 0 (facing +z) and z = w (facing -z)
        patch((x0, below, z0), (s, 0, 0), (0, ws, 0), side, wall_rows, material=3)
        patch((x0, below, z0 + w), (0, ws, 0), (s, 0, 0), wall_rows, side, material=3)
        sphere((x0 + 0.62 * w, 0.2 * height + w / 7, z0 + 0.4 * w), w / 7, 48, 24, material=4)
    light = len(positions)
    rows = math.ceil(rooms / cols)
    x1, z1 = (cols - 1) * pitch + w, (rows - 1) * pitch + w
    y = height + 0.05
    positions += [[0.0, y, 0.0], [x1, y, 0.0], [x1, y, z1], [0.0, y, z1]]  # facing -y
    faces.append((light, light + 1, light + 2, light + 3, 5))

    lines = [f"{p[0]:.6f} {p[1]:.6f} {p[2]:.6f}" for p in positions]
    lines.append("")
    lines.append(": 0.3 0.3 0.3  0.5 0.5 0.5  0 0 0")  # 0: mirror floor
    lines.append(": 0.7 0.7 0.65  0 0 0  0 0 0")  # 1: diffuse ceiling
    lines.append(": 0.35 0.35 0.4  0.3 0.3 0.3  0 0 0")  # 2: mirror-ish walls
    lines.append(": 0.6 0.45 0.3  0 0 0  0 0 0")  # 3: diffuse walls
    lines.append(": 0.5 0.15 0.1  0.3 0.3 0.3  0 0 0")  # 4: mirror-ish sphere
    lines.append(": 0.78 0.78 0.78  0 0 0  6 5 3")  # 5: the light above the skylights
    lines.append("")
    lines += [" ".join(str(k) for k in f) for f in faces]
    lines.append("!")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
