from conftest import assert_png, run_tool
from rtmini_analysis.accuracy import pareto_front

HEADER = "app,scene,knob,value,precision,time_s,memory_bytes,error_name,error,extra\n"


def test_pareto_front_drops_dominated_points():
    rows = [{"time_s": t, "error": e, "id": i} for i, (t, e) in
            enumerate([(1.0, 0.2), (2.0, 0.25), (3.9, 0.1), (5.0, 0.1), (16.0, 0.05), (16.0, 0.06)])]
    assert [r["id"] for r in pareto_front(rows)] == [0, 2, 4]


def test_frontier_printed_and_plot_written(tmp_path):
    sweep = tmp_path / "sweep.csv"
    sweep.write_text(HEADER +
                     "sketchtrace,cornell,spp,1,float,1.0,100,rmse,0.2,x\n"
                     "sketchtrace,cornell,spp,4,float,3.9,100,rmse,0.1,x\n"
                     "sketchtrace,cornell,spp,16,float,16,100,rmse,0.05,x\n"
                     "sketchtrace,cornell,spp,4,double,5.0,200,rmse,0.1,x\n"
                     "sketchtrace,cornell,shadow_samples,8,float,2.0,100,rmse,0.25,x\n"
                     "bake,cube,viewpoints,64,float,2.0,100,rel_mse,0.01,x\n")
    out = tmp_path / "acc.png"
    result = run_tool("accuracy", sweep, "-o", out)
    assert result.returncode == 0, result.stderr
    front = [line.split() for line in result.stdout.splitlines()[1:-1]]
    assert [(r[0], r[3], r[4], r[5]) for r in front] == [
        ("bake", "viewpoints", "64", "float"),
        ("sketchtrace", "spp", "1", "float"), ("sketchtrace", "spp", "4", "float"),
        ("sketchtrace", "spp", "16", "float")]
    width, height = assert_png(out)
    assert width > height  # two panels side by side


def test_error_name_filter_and_bad_rows(tmp_path):
    sweep = tmp_path / "sweep.csv"
    sweep.write_text(HEADER + "bake,cube,viewpoints,64,float,2.0,100,rmse,0.01,\n"
                              "bake,cube,viewpoints,128,float,slow,100,rmse,0.01,\n")
    result = run_tool("accuracy", sweep, "-o", tmp_path / "a.png")
    assert result.returncode == 2
    assert result.stderr.strip() == f"{sweep}:3: 'time_s' is not a number: 'slow'"
    short = tmp_path / "short.csv"
    short.write_text("app,scene,time_s\nbake,cube,1\n")
    result = run_tool("accuracy", short, "-o", tmp_path / "a.png")
    assert result.returncode == 2 and f"{short}:1: missing column(s) knob" in result.stderr
