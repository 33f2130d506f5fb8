"""incise.score against `incise score`: the same lines (the same dicts), the same summary; traces as files
or pose arrays; JIGSAWS motion; bad traces refused naming the file."""
import json
import math

import numpy as np
import pytest

import incise
from conftest import run_cli


def cli_lines(cli, scenario, *traces):
    return [json.loads(line) for line in run_cli(cli, "score", scenario, *traces).splitlines()]


def test_score_gives_the_lines_incise_score_prints(cli, scenarios):
    scenario = str(scenarios / "pad-straight.json")
    traces = [str(scenarios / "traces" / "pad-straight.csv"), str(scenarios / "traces" / "pad-s-curve.csv")]
    expected = cli_lines(cli, scenario, *traces)
    lines = incise.score(scenario, traces)
    assert lines == expected[:-1]
    assert incise.score_summary(lines) == expected[-1]
    assert lines[0]["trace"] == traces[0] and lines[0]["plan"]["share_within_lateral_tolerance"] > 0.9


def test_a_pose_array_scores_as_its_file(scenarios):
    scenario = scenarios / "pad-straight.json"
    trace = scenarios / "traces" / "pad-straight.csv"
    poses = incise.read_trace(trace)
    assert poses.shape[1] == 10 and poses.dtype == np.float64 and np.isnan(poses[:, 9]).all()
    from_file = incise.score(scenario, trace)[0]
    from_array = incise.score(scenario, poses)[0]
    assert from_array["trace"] == "poses[0]"
    assert {k: v for k, v in from_array.items() if k != "trace"} == {k: v for k, v in from_file.items() if k != "trace"}


def test_jigsaws_motion_scores_on_the_session(tmp_path, scenarios):
    # A JIGSAWS-format file (76 columns at 30 Hz): the PSM-left tip on a 2 cm circle above the bunny.
    rows = []
    for k in range(90):
        a = 2 * math.pi * k / 90
        arm = [0.02 * math.cos(a), 0.12, 0.02 * math.sin(a), 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, -0.1]
        rows.append("   " + "   ".join("%.6f" % v for v in (arm * 5)[:76]))
    (tmp_path / "Suturing_C001.txt").write_text("\n".join(rows) + "\n")
    poses = incise.read_jigsaws(tmp_path / "Suturing_C001.txt", arm="psm-left")
    assert poses.shape == (90, 10) and poses[1, 0] == pytest.approx(1 / 30) and poses[0, 8] == 1.0
    scenario = tmp_path / "jig.json"
    scenario.write_text(json.dumps({"tissue": {"mesh": str(scenarios / "meshes" / "bunny.obj"), "scale": 0.01},
                                    "pose_source": {"kind": "trace", "path": str(scenarios / "traces" /
                                                                                 "bunny-straight.csv")}}))
    line = incise.score(scenario, poses)[0]
    assert line["plan"] is None and line["strokes_count"] == 0
    assert line["session"]["path_length_m"] == pytest.approx(2 * math.pi * 0.02 * 89 / 90, abs=0.002)
    (tmp_path / "bad.txt").write_text("1 2 3\n")
    with pytest.raises(incise.InputError, match=r"bad.txt:1: 3 columns, expected 76"):
        incise.read_jigsaws(tmp_path / "bad.txt")
    with pytest.raises(ValueError, match="arm"):
        incise.read_jigsaws(tmp_path / "Suturing_C001.txt", arm="left")


def test_bad_traces_are_refused_naming_the_file(tmp_path, scenarios):
    scenario = scenarios / "pad-straight.json"
    with pytest.raises(ValueError, match="bunny-straight.csv: recorded on another tissue"):
        incise.score(scenario, scenarios / "traces" / "bunny-straight.csv")
    empty = tmp_path / "empty.csv"
    empty.write_text("".join((scenarios / "traces" / "pad-straight.csv").read_text().splitlines(True)[:5]))
    with pytest.raises(ValueError, match="empty.csv: the trace is empty"):
        incise.score(scenario, empty)
    broken = tmp_path / "broken.csv"
    broken.write_text((scenarios / "traces" / "pad-straight.csv").read_text().replace("0.001,", "0.001x,", 1))
    with pytest.raises(incise.InputError, match=r"broken.csv:\d+: column 1"):
        incise.score(scenario, broken)
    with pytest.raises(ValueError, match="N x 10"):
        incise.score(scenario, np.zeros((3, 4)))


def test_a_trace_without_a_tissue_comment_is_scored_with_a_warning(tmp_path, scenarios):
    lines = (scenarios / "traces" / "pad-straight.csv").read_text().splitlines(True)
    bare = tmp_path / "bare.csv"
    bare.write_text("".join(line for line in lines if not line.startswith("# tissue:")))
    with pytest.warns(UserWarning, match="bare.csv carries no tissue hash"):
        line = incise.score(scenarios / "pad-straight.json", bare)[0]
    assert line["strokes_count"] == 1
