"""pyproject.toml's console scripts: one per tool, each resolving to a callable that runs it."""
import importlib
import os
import sys

import pytest

import conftest  # noqa: F401  (puts analysis/ on sys.path)

tomllib = pytest.importorskip("tomllib")

PYPROJECT = os.path.join(conftest.ANALYSIS_DIR, "pyproject.toml")


def scripts():
    with open(PYPROJECT, "rb") as f:
        return tomllib.load(f)["project"]["scripts"]


def test_one_script_per_tool():
    from rtmini_analysis import cli
    targets = {value.split(":")[1] for value in scripts().values()}
    assert targets == set(cli.TOOLS)


@pytest.mark.parametrize("name,target", sorted(scripts().items()))
def test_script_runs_its_tool(name, target, monkeypatch, capsys):
    module, attr = target.split(":")
    entry = getattr(importlib.import_module(module), attr)
    monkeypatch.setattr(sys, "argv", [name, "--help"])
    with pytest.raises(SystemExit) as stop:
        entry()
    assert stop.value.code == 0
    assert "usage" in capsys.readouterr().out.lower()
