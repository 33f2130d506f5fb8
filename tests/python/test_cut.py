"""incise.cut against `incise cut`: the same options give the same mesh (cut.obj's bytes) and summary."""
import json

import numpy as np
import pytest

import incise
from conftest import run_cli


def cli_cut(cli, tmp_path, *options):
    out = tmp_path / "cli"
    run_cli(cli, "cut", "--out", out, *options)
    return (out / "cut.obj").read_bytes(), json.loads((out / "summary.json").read_text())


def without_timings(summary):
    return {key: value for key, value in summary.items() if key != "per_sample"}


def test_the_default_cut_is_the_clis_to_the_byte(cli, tmp_path):
    obj, summary = cli_cut(cli, tmp_path)
    cut = incise.cut()
    cut.save_obj(tmp_path / "python.obj")
    assert (tmp_path / "python.obj").read_bytes() == obj
    assert without_timings(cut.summary) == without_timings(summary)
    assert cut.ok and cut.failure == "" and cut.summary["per_sample"]["count"] == summary["per_sample"]["count"]


def test_options_reach_the_cutter_as_the_clis_do(cli, tmp_path, scenarios):
    mesh = scenarios / "meshes" / "bunny.obj"
    obj, summary = cli_cut(cli, tmp_path, "--mesh", mesh, "--subdivide", "1", "--start", "-0.01", "0", "0.01",
                           "--direction", "1", "0", "0.3", "--length", "0.03", "--depth", "0.003", "--refine", "pn",
                           "--bend", "0.004")
    cut = incise.cut(mesh=mesh, subdivide=1, start=(-0.01, 0, 0.01), direction=[1, 0, 0.3], length=0.03,
                     depth=0.003, refine="pn", bend=0.004)
    cut.save_obj(tmp_path / "python.obj")
    assert (tmp_path / "python.obj").read_bytes() == obj
    assert without_timings(cut.summary) == without_timings(summary)
    assert cut.summary["options"]["refine"] == "pn" and cut.summary["options"]["depth_m"] == 0.003


def test_a_cut_has_wall_faces_and_seam_vertices(tmp_path):
    cut = incise.cut(length=0.03)
    assert cut.vertices.shape[1] == 3 and cut.faces.dtype == np.int64
    assert cut.wall.sum() == cut.summary["mesh"]["wall_faces"] > 0
    assert (cut.face_kinds == 2).sum() == cut.wall.sum()
    assert (cut.mesh.vertex_kinds == 1).sum() == cut.summary["mesh"]["seam_vertices"]
    assert not cut.vertices.flags.writeable


def test_bad_options_raise_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="refine"):
        incise.cut(refine="curvy")
    with pytest.raises(ValueError, match="start: expected 3"):
        incise.cut(start=(0, 0))
    with pytest.raises(TypeError, match="length"):
        incise.cut(length="long")
    with pytest.raises(FileNotFoundError, match="nothing.obj"):
        incise.cut(mesh=tmp_path / "nothing.obj")
    with pytest.raises(ValueError, match="first ray"):
        incise.cut(start=(5.0, 0.0, 5.0))


def test_the_docstring_gives_the_clis_defaults():
    assert "0.05" in incise.cut.__doc__ and "linear" in incise.cut.__doc__
