import pytest

from conftest import assert_png, parse_table, run_tool, write_summary
from rtmini_analysis.scaling import scaling_table


def test_strong_scaling_table_and_plot(tmp_path):
    files = []
    for ranks, seconds in [(1, 8.0), (2, 4.2), (4, 2.5), (8, 1.6)]:
        files.append(tmp_path / f"strong-{ranks}.json")
        write_summary(files[-1], ranks, seconds)
    out = tmp_path / "strong.png"
    result = run_tool("scaling", "--mode", "strong", *files, "-o", out)
    assert result.returncode == 0, result.stderr
    table = parse_table(result.stdout)
    assert table["1"][1:] == ["8.0000", "1.000", "1.000"]
    assert table["2"][1:] == ["4.2000", "1.905", "0.952"]
    assert table["8"][1:] == ["1.6000", "5.000", "0.625"]
    width, height = assert_png(out)
    assert width > 2 * height  # three panels side by side


def test_weak_scaling_relative_to_smallest_run(tmp_path):
    files = []
    for ranks, seconds in [(2, 5.0), (4, 5.0), (8, 6.25)]:
        files.append(tmp_path / f"weak-{ranks}.json")
        write_summary(files[-1], ranks, seconds)
    result = run_tool("scaling", "--mode", "weak", *files, "-o", tmp_path / "weak.png")
    assert result.returncode == 0, result.stderr
    table = parse_table(result.stdout)
    assert table["4"][1:] == ["5.0000", "4.000", "1.000"]
    assert table["8"][1:] == ["6.2500", "6.400", "0.800"]
    assert_png(tmp_path / "weak.png")


def test_repeats_use_median_and_sum_of_phases_without_total(tmp_path):
    rows = scaling_table({1: [9.0, 10.0, 30.0], 2: [5.0]}, "strong")
    assert rows[0][1] == 10.0 and rows[1][2] == pytest.approx(2.0)
    path = tmp_path / "p.json"
    write_summary(path, 1, None, phases={"setup": 1.0, "trace": 2.5})
    other = tmp_path / "q.json"
    write_summary(other, 2, 1.75)
    result = run_tool("scaling", path, other, "-o", tmp_path / "s.png")
    assert parse_table(result.stdout)["2"][1:] == ["1.7500", "2.000", "1.000"]


def test_bad_summary_reports_file_and_line(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{"app": "bake",\n "ranks": }\n')
    result = run_tool("scaling", path, "-o", tmp_path / "s.png")
    assert result.returncode == 2
    assert result.stderr.startswith(f"{path}:2: not JSON")
    missing = tmp_path / "missing.json"
    missing.write_text('{"app": "bake"}')
    result = run_tool("scaling", missing, "-o", tmp_path / "s.png")
    assert result.returncode == 2 and "missing key 'version'" in result.stderr
