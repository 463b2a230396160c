import base64
import re

from conftest import assert_png, parse_table, run_tool, write_timings


def test_single_run_report(tmp_path):
    write_timings(tmp_path / "bake.h5", [2.0, 4.0], strategy="static", app="bake", iterations=2,
                  allgather=0.5, rays=[3000, 5000])
    stem = tmp_path / "out" / "report"
    result = run_tool("timing_report", tmp_path / "bake.h5", "-o", stem)
    assert result.returncode == 0, result.stderr
    row = parse_table(result.stdout)["bake_static_(2_ranks)"]
    # wall 4 s; max/mean 4/3; 8000 rays / 4 s; 4 x 0.5 s all-gather and 2 s idle of 2 x 4 rank-s
    assert row[1:] == ["4.0000", "1.333", "2000", "25.0%", "25.0%"]
    markdown = (tmp_path / "out" / "report.md").read_text()
    assert "| setup | 1.333 | 1 |" in markdown and "iterations: 2" in markdown
    for name in re.findall(r"\]\((report_files/[^)]+\.png)\)", markdown):
        assert_png(tmp_path / "out" / name, min_width=150, min_height=100)
    page = (tmp_path / "out" / "report.html").read_text()
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', page)
    assert len(images) == 2 and "<img" in page and 'src="report_files' not in page
    assert all(base64.b64decode(img)[:8] == b"\x89PNG\r\n\x1a\n" for img in images)


def test_sweep_report_has_comparison_plot(tmp_path):
    files = []
    for strategy, times in [("static", [1.0, 2.0, 3.0, 6.0]), ("bargain", [3.0, 3.0, 3.1, 3.2])]:
        files.append(tmp_path / f"{strategy}.h5")
        write_timings(files[-1], times, strategy=strategy)
    stem = tmp_path / "sweep"
    result = run_tool("timing_report", *files, "-o", stem)
    assert result.returncode == 0, result.stderr
    table = parse_table(result.stdout)
    assert table["sketchtrace_static_(4_ranks)"][2] == "2.000"
    assert table["sketchtrace_bargain_(4_ranks)"][5] == "3.9%"  # (0.2+0.2+0.1+0) / (4 x 3.2)
    assert_png(tmp_path / "sweep_files" / "sweep.png")
    assert len(re.findall("data:image/png;base64", (tmp_path / "sweep.html").read_text())) == 5


def test_zero_iterations_allowed(tmp_path):
    write_timings(tmp_path / "t.h5", [1.0], iterations=0)
    result = run_tool("timing_report", tmp_path / "t.h5", "-o", tmp_path / "r")
    assert result.returncode == 0, result.stderr
    assert parse_table(result.stdout)["sketchtrace_static_(1_ranks)"][4] == "0.0%"
