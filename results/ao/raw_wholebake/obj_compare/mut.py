#!/usr/bin/env python3
"""Differential check of two OBJ readers: mut.py DUMP_OLD DUMP_NEW WORKDIR.

DUMP_* are dump.cpp built against the two readers (each prints the Mesh of every OBJ named on its
command line, or the error). Writes 1500 OBJ files made by random line edits of edge/*.obj and
inputs/meshes/CornellBox-Original.obj into WORKDIR (with edge/'s material libraries) and prints
those whose dumps differ, then the count. Run from the repository root."""
import glob
import os
import random
import shutil
import subprocess
import sys

old, new, work = sys.argv[1], sys.argv[2], sys.argv[3]
here = os.path.dirname(os.path.abspath(__file__))
os.makedirs(work, exist_ok=True)
for mtl in glob.glob(os.path.join(here, "edge", "*.mtl")):
    shutil.copy(mtl, work)
random.seed(7)
srcs = [open(f).read() for f in sorted(glob.glob(os.path.join(here, "edge", "*.obj")))]
srcs.append(open("inputs/meshes/CornellBox-Original.obj").read())
tokens = ['v', 'vt', 'vn', 'f', 'g', 'o', 'usemtl', 'mtllib', '#', '/', '//', '-1', '0', '1', '2',
          '3', ' ', '\t', '\r', '\n', 'a', 'b', 'c', 'l1.mtl', 'l2.mtl', '1e3', 'nan', '.5', '+1',
          '-', 's', 'l', 'p']
statements = ['g', 'g ', 'o', 'o x', 'usemtl a', 'usemtl c', 'mtllib l2.mtl',
              'mtllib l1.mtl l2.mtl', 'f 1 2 3', 'f -1 -2 -3 -4 -5', 'vt 1', 'v 1 2 3']
files = []
for i in range(1500):
    lines = random.choice(srcs).split('\n')
    for _ in range(random.randint(1, 4)):
        op = random.random()
        k = random.randrange(len(lines))
        if op < 0.25:
            lines.insert(k, random.choice(lines))
        elif op < 0.4:
            del lines[k]
        elif op < 0.7:
            s = lines[k]
            j = random.randint(0, len(s))
            lines[k] = s[:j] + random.choice(tokens) + s[j:]
        elif op < 0.85:
            s = lines[k]
            if s:
                j = random.randrange(len(s))
                lines[k] = s[:j] + s[j + 1:]
        else:
            lines.insert(k, random.choice(statements))
    name = 'm%04d.obj' % i
    open(os.path.join(work, name), 'w').write('\n'.join(lines))
    files.append(name)
diff = 0
for i in range(0, len(files), 100):
    chunk = files[i:i + 100]
    a = subprocess.run([old] + chunk, capture_output=True, text=True, cwd=work).stdout.split('== ')
    b = subprocess.run([new] + chunk, capture_output=True, text=True, cwd=work).stdout.split('== ')
    for x, y in zip(a, b):
        if x != y:
            diff += 1
            xl, yl = x.split('\n'), y.split('\n')
            print('DIFF', xl[0])
            for p, q in zip(xl, yl):
                if p != q:
                    print('  old:', p[:150])
                    print('  new:', q[:150])
                    break
print('cases', len(files), 'diffs', diff)
