"""Split a raw Bake Shop (.bs) mesh at material boundaries (and optionally creases).

The bake gives each vertex the plain average of its faces' materials and the area-weighted
average of their normals (miniapps/bake/bake_scene.hpp). Where faces of different materials
(or orientations) meet, that average leaks across the edge. Giving every face group its own
copy of a shared vertex removes the leak, so baking the split mesh measures the error of the
averaging (results/accuracy/model.md).

Usage: python3 bs_split_creases.py IN.bs OUT.bs --by material|material+normal|face [--inset F]
A vertex is copied once per distinct key of the faces that use it: the face's material, with
material+normal also its unit normal rounded to 1e-3, with face the face itself. --inset F
(with --by face) moves every corner the fraction F of the way to its face's centroid, so that
no vertex lies on another face's plane (a vertex on a concave edge otherwise starts its shadow
rays on the adjacent face). Raw files only (no viewpoint lines).
"""
import argparse
import sys


def read_bs(path):
    with open(path) as f:
        lines = f.read().split("\n")
    sections, current = [], []
    for line in lines:
        if line.strip() == "!":
            sections.append(current)
            break
        if line.strip() == "":
            sections.append(current)
            current = []
        else:
            current.append(line)
    if len(sections) != 3:
        sys.exit(f"{path}: expected vertices, materials and faces sections ending in '!'")
    vertices = []
    for n, line in enumerate(sections[0], 1):
        if line.lstrip().startswith("|"):
            sys.exit(f"{path}:{n}: viewpoint lines: give a raw (unbaked) file")
        vertices.append([float(x) for x in line.split()])
    faces = [[int(x) for x in line.split()] for line in sections[2]]
    return vertices, sections[1], faces


def face_normal(vertices, idx):
    a, b, c = (vertices[i] for i in idx[:3])
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = sum(x * x for x in n) ** 0.5
    return tuple(round(x / length, 3) + 0.0 for x in n) if length > 0 else (0.0, 0.0, 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--by", choices=["material", "material+normal", "face"],
                    default="material")
    ap.add_argument("--inset", type=float, default=0.0)
    args = ap.parse_args()
    vertices, materials, faces = read_bs(args.input)
    copies = {}  # (old vertex, key) -> new vertex
    out_vertices, out_faces = [], []
    for face in faces:
        idx, material = face[:-1], face[-1]
        key = (material, face_normal(vertices, idx)) if args.by == "material+normal" else material
        if args.by == "face":
            key = len(out_faces)
        centre = [sum(vertices[i][k] for i in idx) / len(idx) for k in range(3)]
        new = []
        for i in idx:
            if (i, key) not in copies:
                copies[(i, key)] = len(out_vertices)
                p = vertices[i]
                if args.by == "face" and args.inset > 0:
                    p = [p[k] + args.inset * (centre[k] - p[k]) for k in range(3)]
                out_vertices.append(p)
            new.append(copies[(i, key)])
        out_faces.append(new + [material])
    with open(args.output, "w") as f:
        f.write("".join(" ".join(repr(x) for x in v) + "\n" for v in out_vertices))
        f.write("\n" + "".join(m + "\n" for m in materials))
        f.write("\n" + "".join(" ".join(str(x) for x in fc) + "\n" for fc in out_faces))
        f.write("!\n")
    print(f"{args.input}: {len(vertices)} vertices -> {len(out_vertices)} ({args.by})")


if __name__ == "__main__":
    main()
