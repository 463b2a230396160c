#!/usr/bin/env python3
# CPU seconds of clang++ -fsyntax-only (what ctest clang.syntax runs) against a full -O3 compile of
# the same translation units, with the build's own flags (tests/clang/clang_syntax.py).
# Usage (repository root, after a build into build/): python3 results/ci/clang_codegen_ratio.py FILE...
import json, shlex, subprocess, sys, os, time, resource
sys.path.insert(0, 'tests/clang')
from clang_syntax import clang_command
e = json.load(open('build/compile_commands.json'))
for want in sys.argv[1:]:
    ent = [x for x in e if x['file'].endswith(want)][0]
    base = clang_command(ent, '/usr/bin/clang++')
    for mode in ('syntax', 'O3'):
        cmd = base if mode == 'syntax' else [a for a in base if a != '-fsyntax-only'] + ['-c', '-o', '/tmp/clang_ratio.o']
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(['nice'] + cmd, cwd=ent['directory'], check=True)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        print(want, mode, round(r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime, 2), 'CPU s', flush=True)
