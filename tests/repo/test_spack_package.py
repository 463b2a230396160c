"""The Spack recipe (packaging/spack) maps every variant to something real.

Read without Spack: the recipe is parsed with `ast`, the CMake options with regular expressions
over every CMakeLists.txt and *.cmake file. A variant must switch a declared RTMINI_* option or
pick a Kokkos backend that the recipe forwards to its kokkos dependency; every RTMINI_* name the
recipe passes must be declared.
"""
import ast
import os
import re

import pytest

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))
RECIPE = os.path.join(ROOT, "packaging", "spack", "packages", "rtmini", "package.py")
DECLARED = re.compile(r"\boption\(\s*(RTMINI_\w+)|\bset\(\s*(RTMINI_\w+)\s[^)]*?\bCACHE\b", re.S)


def cmake_options(root=ROOT):
    names = set()
    for d, dirs, files in os.walk(root):
        dirs[:] = [x for x in dirs if not x.startswith((".", "build")) and x != "node_modules"]
        for f in files:
            if f == "CMakeLists.txt" or f.endswith(".cmake"):
                with open(os.path.join(d, f), errors="replace") as fh:
                    names.update(a or b for a, b in DECLARED.findall(fh.read()))
    return names


def recipe_facts(source):
    """(declared variants, {variant: option}, backend variants, RTMINI_* strings, depends_on specs)."""
    tree = ast.parse(source)
    variants, table, backends, specs = set(), {}, (), []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.args:
            first = node.args[0]
            if node.func.id == "variant" and isinstance(first, ast.Constant):
                variants.add(first.value)
            if node.func.id == "depends_on" and isinstance(first, (ast.Constant, ast.JoinedStr)):
                when = next((k.value for k in node.keywords if k.arg == "when"), None)
                spec = first.value if isinstance(first, ast.Constant) else ast.unparse(first)
                specs.append((spec, ast.unparse(when) if when is not None else ""))
        if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name):
            if node.targets[0].id == "variant_options":
                table = ast.literal_eval(node.value)
            if node.targets[0].id == "kokkos_backend_variants":
                backends = ast.literal_eval(node.value)
    strings = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)
               and isinstance(n.value, str) and re.fullmatch(r"RTMINI_\w+", n.value)}
    return variants, table, backends, strings, specs


def problems(source, options):
    variants, table, backends, strings, specs = recipe_facts(source)
    found = []
    for v in sorted(variants | set(backends)):
        if v not in table and v not in backends:
            found.append(f"variant {v} maps to no RTMINI_* option and is no Kokkos backend")
    for v, option in sorted(table.items()):
        if v not in variants:
            found.append(f"variant_options names {v}, which is not a declared variant")
        if option not in options:
            found.append(f"variant {v} maps to {option}, which CMakeLists.txt does not declare")
    for name in sorted(strings - options):
        found.append(f"the recipe passes {name}, which CMakeLists.txt does not declare")
    for b in backends:
        if not any(s.startswith("kokkos") and f"+{b}" in s and f"+{b}" in w for s, w in specs):
            found.append(f"backend variant {b} is not forwarded to kokkos (depends_on kokkos+{b} when +{b})")
    return found


def read_recipe():
    with open(RECIPE) as f:
        return f.read()


def test_every_variant_maps_to_a_declared_option():
    options = cmake_options()
    assert {"RTMINI_ENABLE_MPI", "RTMINI_ENABLE_PNG", "RTMINI_HOST_ARCH"} <= options
    assert problems(read_recipe(), options) == []


@pytest.mark.parametrize("old,new,expect", [
    ('"png": "RTMINI_ENABLE_PNG"', '"png": "RTMINI_ENABLE_PGN"', "RTMINI_ENABLE_PGN"),
    ('self.define("RTMINI_HOST_ARCH", "")', 'self.define("RTMINI_HOST_ARC", "")', "RTMINI_HOST_ARC"),
    ('variant("double", default=False', 'variant("quad", default=False', "variant quad"),
    ('depends_on("kokkos+openmp", when="+openmp")', '', "backend variant openmp"),
])
def test_a_broken_recipe_is_caught(old, new, expect):
    source = read_recipe()
    assert old in source
    found = problems(source.replace(old, new), cmake_options())
    assert any(expect in p for p in found), found
