import pytest

from conftest import assert_png, parse_table, run_tool, write_timings


def test_prints_max_mean_and_imbalance_per_strategy(tmp_path):
    write_timings(tmp_path / "static.h5", [1.0, 2.0, 3.0, 6.0], strategy="static")
    write_timings(tmp_path / "bargain.h5", [3.0, 3.0, 3.1, 3.2], strategy="bargain")
    out = tmp_path / "ranks.png"
    result = run_tool("rank_completion", tmp_path / "bargain.h5", tmp_path / "static.h5", "-o", out)
    assert result.returncode == 0, result.stderr
    table = parse_table(result.stdout)
    assert list(table) == ["static", "bargain"]  # the paper's ladder order, not argument order
    assert table["static"][1:] == ["4", "6.0000", "3.0000", "1.0000", "2.000"]
    assert table["bargain"][1:] == ["4", "3.2000", "3.0750", "3.0000", "1.041"]
    width, height = assert_png(out)
    assert height > width / 2  # two rows of panels


def test_one_strategy_makes_one_row(tmp_path):
    write_timings(tmp_path / "queue.h5", [2.0] * 16, strategy="queue")
    out = tmp_path / "one.png"
    result = run_tool("rank_completion", tmp_path / "queue.h5", "-o", out)
    assert result.returncode == 0, result.stderr
    assert parse_table(result.stdout)["queue"][-1] == "1.000"
    width, height = assert_png(out)
    assert height < width / 2


def test_duplicate_strategy_is_bad_input(tmp_path):
    write_timings(tmp_path / "a.h5", [1.0, 2.0], strategy="static")
    write_timings(tmp_path / "b.h5", [1.0, 2.0], strategy="static")
    result = run_tool("rank_completion", tmp_path / "a.h5", tmp_path / "b.h5", "-o", tmp_path / "x.png")
    assert result.returncode == 2
    assert "already given" in result.stderr
    assert not (tmp_path / "x.png").exists()


def test_labels_name_rows_of_one_strategy(tmp_path):
    write_timings(tmp_path / "a.h5", [1.0, 2.0], strategy="steal")
    write_timings(tmp_path / "b.h5", [1.9, 2.0], strategy="steal")
    out = tmp_path / "x.png"
    result = run_tool("rank_completion", tmp_path / "a.h5", tmp_path / "b.h5", "-o", out,
                      "--labels", "steal,steal+thread")
    assert result.returncode == 0, result.stderr
    table = parse_table(result.stdout)
    assert list(table) == ["steal", "steal+thread"]  # given order
    assert table["steal+thread"][-1] == "1.026"
    bad = run_tool("rank_completion", tmp_path / "a.h5", tmp_path / "b.h5", "-o", tmp_path / "y.png",
                   "--labels", "one")
    assert bad.returncode == 2 and "2 files" in bad.stderr


@pytest.mark.parametrize("damage, message", [
    (lambda f: f.__delitem__("ranks/completion_time"), "missing dataset '/ranks/completion_time'"),
    (lambda f: f.attrs.__setitem__("ranks", 3), "has shape (2, 3), expected (3, 3)"),
    (lambda f: f.attrs.__delitem__("strategy"), "missing root attribute 'strategy'"),
    (lambda f: f.attrs.__setitem__("parameters", "{oops"), "'parameters' is not JSON"),
])
def test_malformed_timings_name_file_and_reason(tmp_path, damage, message):
    import h5py

    path = tmp_path / "bad.h5"
    write_timings(path, [1.0, 2.0])
    with h5py.File(path, "a") as f:
        damage(f)
    result = run_tool("rank_completion", path, "-o", tmp_path / "x.png")
    assert result.returncode == 2
    assert result.stderr.startswith(f"{path}: ")
    assert message in result.stderr


def test_not_hdf5_is_bad_input(tmp_path):
    path = tmp_path / "text.h5"
    path.write_text("stub timings\n")
    result = run_tool("rank_completion", path, "-o", tmp_path / "x.png")
    assert result.returncode == 2 and "not a readable HDF5 file" in result.stderr
