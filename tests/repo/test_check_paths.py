"""The path checker finds each kind of outside reference and leaves clean trees alone."""
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))
import check_paths  # noqa: E402


def make_tree(tmp_path, files):
    for rel, text in files.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return str(tmp_path)


def run(tmp_path, files, capsys):
    root = make_tree(tmp_path, files)
    code = check_paths.main(["check_paths.py", root])
    return code, capsys.readouterr().out


SIBLING = "../" + "shared"


@pytest.mark.parametrize("rel,text", [
    ("inputs/ao/x.toml", f'file = "../../../{SIBLING[3:]}/scenes/spot.obj"\n'),
    ("inputs/ao/y.toml", f'file = "{SIBLING}/scenes/spot.obj"\n'),
    ("tests/CMakeLists.txt", 'set(D "${PROJECT_SOURCE_DIR}/../data")\n'),
    ("jobs/run.sh", "python3 /" + "work/main/analysis/x.py\n"),
    ("README.md", "see /" + "root/notes/plan.md\n"),
    ("inputs/m/a.obj", "mtllib ../../../elsewhere/a.mtl\n"),
    ("results/bake/run.sh", f'gen --scene "$src/{SIBLING}/scenes/bunny.obj"\n'),
])
def test_each_kind_of_outside_reference_fails(tmp_path, capsys, rel, text):
    code, out = run(tmp_path, {rel: text}, capsys)
    assert code == 1
    assert out.startswith(f"{rel}:1: ")


def test_checkout_path_is_found(tmp_path, capsys):
    code, out = run(tmp_path, {"a.cmake": f"include({tmp_path}/x.cmake)\n"}, capsys)
    assert code == 1 and "absolute path" in out


def test_clean_tree_passes(tmp_path, capsys):
    files = {
        "inputs/ao/x.toml": 'file = "../meshes/spot.obj"\n',
        "tests/CMakeLists.txt": 'set(D "${PROJECT_SOURCE_DIR}/inputs/meshes")\nset(W ${CMAKE_CURRENT_BINARY_DIR}/work)\n',
        "jobs/local/a.sh": 'root=$(cd "$(dirname "$0")/../.." && pwd)\n',
        "common/src/a.cpp": '#include "../include/a.hpp"\n',
        "results/x/README.md": "measured in /" + "work/main on host h\n",
    }
    code, out = run(tmp_path, files, capsys)
    assert code == 0, out
