"""incise.replay and incise.World against `incise replay --fast`: the same geometry hash, the same report;
a world stepped frame by frame from Python makes the same cut."""
import threading

import numpy as np
import pytest

import incise
from conftest import fnv1a_hash

TIMINGS = ("wall_s", "latency", "loop")


def without_timings(report):
    return {key: value for key, value in report.items() if key not in TIMINGS}


@pytest.mark.parametrize("name", ["bunny-straight", "pad-straight", "bunny-crossing"])
def test_replay_makes_the_clis_geometry_and_report(cli_replays, scenarios, tmp_path, name):
    report, obj = cli_replays(name)
    result = incise.replay(scenarios / f"{name}.json")
    assert result.geometry_hash == report["geometry_hash"]
    assert without_timings(result.report) == without_timings(report)
    result.save_obj(tmp_path / "cut.obj")
    assert (tmp_path / "cut.obj").read_bytes() == obj.read_bytes()


def test_the_replays_arrays_are_the_hashed_mesh(scenarios):
    result = incise.replay(scenarios / "pad-straight.json")
    assert fnv1a_hash(result.vertices, result.faces, result.face_kinds) == result.geometry_hash
    assert result.wall.sum() == result.report["mesh"]["wall_faces"] > 0
    assert not result.vertices.flags.writeable


def test_replay_in_real_time_gives_the_same_geometry(cli_replays, scenarios):
    report, _ = cli_replays("pad-straight")
    result = incise.replay(scenarios / "pad-straight.json", fast=False)
    assert result.report["mode"] == "realtime" and result.geometry_hash == report["geometry_hash"]


def step_like_replay(world, poses):
    """Frame k at t0 + k period takes the poses due by then (as `incise replay --fast` feeds them), until
    every pose is in, nothing is pending and the settle time is over. Returns the steps' forces."""
    t0, period = poses[0, 0], world.period_s
    end = poses[-1, 0] + world.settle_s
    fed = taken = k = 0
    forces = []
    while True:
        t = t0 + k * period
        while fed < len(poses) and poses[fed, 0] <= t + 1e-12:
            fed += 1
        step = world.step(poses[taken:fed], period, t)
        taken = fed
        forces.append(step.force_N)
        if taken == len(poses) and not step.pending and t >= end:
            return np.array(forces)
        k += 1


def test_a_world_stepped_from_python_equals_the_replay(cli_replays, scenarios):
    report, _ = cli_replays("bunny-straight")
    world = incise.World.from_scenario(scenarios / "bunny-straight.json")
    forces = step_like_replay(world, world.poses)
    assert world.geometry_hash == report["geometry_hash"]
    assert world.incisions == report["incisions"] and len(forces) == report["frames"]
    assert world.incision_figures == report["incision_figures"]
    assert np.linalg.norm(forces, axis=1).max() <= 8.0 + 1e-9  # the tool's max_force_N


def test_run_steps_in_cpp_as_the_replay_does(cli_replays, scenarios):
    report, _ = cli_replays("pad-straight")
    world = incise.World.from_scenario(scenarios / "pad-straight.json")
    frames = world.run()
    assert world.geometry_hash == report["geometry_hash"] and len(frames["t_s"]) == report["frames"]
    assert frames["force_N"].shape == (report["frames"], 3) and frames["contact"].dtype == np.bool_
    assert frames["contact"].any() and frames["cutting"].sum() <= frames["contact"].sum()
    assert np.all(np.diff(frames["t_s"]) > 0)


def test_a_worlds_arrays_are_copies_of_its_mesh_now(scenarios):
    world = incise.World.from_scenario(scenarios / "pad-straight.json")
    before = world.vertices
    snapshot = world.mesh()
    assert before.flags.owndata and before.flags.writeable and before.dtype == np.float64
    world.run()
    after = world.vertices
    assert len(after) > len(before), "the cut added vertices; the earlier copy kept its own"
    assert snapshot.geometry_hash != world.geometry_hash and len(snapshot.vertices) == len(before)
    assert world.faces.shape == (len(world.face_kinds), 3) and (world.face_kinds == 2).any()
    assert fnv1a_hash(after, world.faces, world.face_kinds) == world.geometry_hash


def test_a_simulated_worlds_tissue_as_simulated_and_at_rest_are_the_replays(cli_replays, scenarios, tmp_path):
    report, obj = cli_replays("pad-tension")
    world = incise.World.from_scenario(scenarios / "pad-tension.json")
    before = world.physics
    assert before["simulated"] and before["steps"] == 0 and before["rate_hz"] >= 100
    world.run()
    after = world.physics
    assert world.geometry_hash == report["geometry_hash"]
    assert after["steps"] > 100 and after["nodes"] > before["nodes"] and after["tets"] > before["tets"]
    assert after["max_displacement_m"] > 1e-4 and after["press_force_N"].shape == (3,)
    world.simulated_mesh().save_obj(tmp_path / "cut.obj")
    world.mesh().save_obj(tmp_path / "cut_rest.obj")
    assert (tmp_path / "cut.obj").read_bytes() == obj.read_bytes()
    assert (tmp_path / "cut_rest.obj").read_bytes() == (obj.parent / "cut_rest.obj").read_bytes()
    now, rest = world.simulated_vertices, world.vertices
    assert now.shape == rest.shape and np.isfinite(now).all()
    assert np.linalg.norm(now - rest, axis=1).max() > 5e-4, "the wound gapes by the tissue's tension"


def test_a_tissue_without_a_material_is_not_simulated(scenarios):
    world = incise.World.from_scenario(scenarios / "pad-straight.json")
    world.run()
    assert world.physics == {"simulated": False}
    assert np.array_equal(world.simulated_vertices, world.vertices)


def test_a_world_over_a_mesh_with_options(scenarios):
    mesh = incise.load_mesh(scenarios / "meshes" / "bunny.obj", scale=0.01, subdivide=2)
    world = incise.World(mesh, depth_m=0.003, stiffness_N_per_m=500.0, refine="off")
    assert world.poses.shape == (0, 10) and world.period_s == 0.001
    poses = incise.World.from_scenario(scenarios / "bunny-straight.json").poses
    world.run(poses)
    figures = world.incision_figures
    assert len(figures) == 1 and figures[0]["groove_length_m"] > 0.03
    with pytest.raises(ValueError, match="unknown option 'depth'"):
        incise.World(mesh, depth=0.003)
    with pytest.raises(ValueError, match="no poses"):
        world.run(np.zeros((0, 10)))


def test_a_step_reports_force_and_contact_in_numpy(scenarios):
    world = incise.World.from_scenario(scenarios / "pad-straight.json")
    c = np.sqrt(0.5)  # the blade (the tool's -z) pointing down -y, into the pad (its top at y = 0)
    above = np.array([0.0, 0.0, 0.01, 0.0, c, -c, 0, 0, 1, np.nan])
    step = world.step(above, 0.001, 0.0)
    assert not step.contact and step.force_N.shape == (3,) and np.all(step.force_N == 0)
    assert step.poses_used == 1 and step.poses_rejected == 0
    # Down at 5 cm/s to 2 mm into the pad, a pose a frame (the haptic part keeps up with a hand's speed).
    for k in range(1, 241):
        inside = above.copy()
        inside[0], inside[2] = 0.001 * k, 0.01 - 0.00005 * k
        step = world.step(inside.reshape(1, 10), 0.001, 0.001 * k)
    assert step.contact and step.force_N[1] > 0.5 and step.penetration_m == pytest.approx(0.002, abs=1e-4)
    assert np.allclose(step.normal, [0, 1, 0]) and step.tip_m[1] == pytest.approx(-0.002)
    backwards = inside.copy()
    backwards[0] = 0.1  # not after the previous pose: skipped and counted
    assert world.step(backwards, 0.001, 0.241).poses_rejected == 1
    assert world.step(np.zeros((0, 10)), 0.001, 0.242).poses_used == 0
    with pytest.raises(ValueError, match="N x 10"):
        world.step(np.zeros((2, 9)), 0.001, 0.243)
    with pytest.raises(ValueError, match="dt_s"):
        world.step(above, 0.0, 0.243)
    with pytest.raises(ValueError, match="buttons"):
        world.step(np.array([0.3, 0, 0, 0, 1, 0, 0, 0, 0.5, np.nan]), 0.001, 0.243)


def test_a_second_thread_is_refused_while_run_works(scenarios):
    world = incise.World.from_scenario(scenarios / "bunny-straight.json")
    errors = []
    started = threading.Event()

    def run():
        started.set()
        world.run()

    thread = threading.Thread(target=run)
    thread.start()
    started.wait()
    for _ in range(2000):
        try:
            world.step(np.zeros((0, 10)), 0.001, 100.0)
        except RuntimeError as error:
            errors.append(str(error))
            break
    thread.join()
    assert errors and "in use by another thread" in errors[0]


def test_bad_scenarios_raise_input_error_naming_the_file(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{ "tissue": { "mesh": "nothing.obj" }, "pose_source": { "kind": "trace", "path": "t.csv" } }')
    with pytest.raises(incise.InputError, match="bad.json"):
        incise.replay(bad)
    with pytest.raises(incise.InputError, match="bad.json"):
        incise.World.from_scenario(bad)
    with pytest.raises(FileNotFoundError):
        incise.replay(tmp_path / "none.json")
