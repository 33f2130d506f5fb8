#!/usr/bin/python3
"""The Python module's costs (docs/benchmarks.md, "The Python module"): what a World.step call from Python
costs beyond the C++ step, and what reading a large mesh's arrays costs. Prints JSON; not a test.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py [--repeats 5] [--subdivide 5]

1. Step overhead: a scenario's frames (bunny-straight: 1363 frames, one pose in most) stepped twice over
   fresh worlds, once by World.step from a Python loop (the frames' pose arrays made beforehand) and once
   by World.run, the same frames stepped in C++; (Python - C++) / frames is the binding's cost per step.
   Also a world whose blade stays above the tissue (the C++ step does almost nothing): a call's whole cost.
2. Arrays: the bunny Loop-subdivided (5 rounds: 1.9 million vertices) read as Mesh.vertices (a view),
   Mesh.faces (gathered once, then a view), World.vertices and World.faces (copies), against numpy copying
   the same bytes (the machine's memory speed).
"""
import argparse
import json
import os
import platform
import statistics
import time

import numpy as np

import incise


def frames_of(world):
    """The scenario's poses grouped per frame as `incise replay --fast` feeds them: [(poses, t_s)]."""
    poses, period = world.poses, world.period_s
    end = poses[-1, 0] + world.settle_s
    frames, fed, k = [], 0, 0
    while True:
        t = poses[0, 0] + k * period
        first = fed
        while fed < len(poses) and poses[fed, 0] <= t + 1e-12:
            fed += 1
        frames.append((np.ascontiguousarray(poses[first:fed]), t))
        if fed == len(poses) and t >= end:
            return frames
        k += 1


def step_overhead(scenario, repeats):
    python_s, cpp_s = [], []
    for _ in range(repeats):
        world = incise.World.from_scenario(scenario)
        frames = frames_of(world)
        dt = world.period_s
        start = time.perf_counter()
        for poses, t in frames:
            world.step(poses, dt, t)
        python_s.append(time.perf_counter() - start)
        steps = len(frames)
        while world.pending:  # the run below steps until nothing is pending: count those frames too
            world.step(np.zeros((0, 10)), dt, frames[-1][1] + dt * (steps - len(frames) + 1))
            steps += 1
        world = incise.World.from_scenario(scenario)
        start = time.perf_counter()
        cpp_frames = len(world.run()["t_s"])
        cpp_s.append(time.perf_counter() - start)
        assert cpp_frames == steps, (cpp_frames, steps)
    py, cpp = statistics.median(python_s), statistics.median(cpp_s)
    return {"frames": steps, "python_loop_s": py, "cpp_loop_s": cpp, "python_us_per_step": 1e6 * py / steps,
            "cpp_us_per_step": 1e6 * cpp / steps, "binding_us_per_step": 1e6 * (py - cpp) / steps,
            "one_pose_frames": sum(1 for p, _ in frames if len(p) == 1)}


def idle_call(scenario, calls):
    """World.step with one pose far above the tissue: the C++ step finds no contact and no work."""
    world = incise.World.from_scenario(scenario)
    pose = np.array([0.0, 0.0, 0.5, 0.0, 1, 0, 0, 0, 0, np.nan])
    per_call = []
    for r in range(5):
        start = time.perf_counter()
        for k in range(calls):
            pose[0] = (r * calls + k) * 1e-3
            world.step(pose, 1e-3, pose[0])
        per_call.append((time.perf_counter() - start) / calls)
    step = world.step(pose, 1e-3, 1e6)
    start = time.perf_counter()
    for _ in range(calls):
        step.force_N
    force = (time.perf_counter() - start) / calls
    return {"calls": calls, "us_per_call": 1e6 * statistics.median(per_call), "force_N_read_us": 1e6 * force}


def timed(call, repeats=5):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def arrays(subdivide):
    mesh = incise.load_mesh(incise.shipped("meshes/bunny.obj"), scale=0.01, subdivide=subdivide)
    start = time.perf_counter()
    faces = mesh.faces  # gathered from the half-edge structure on first use
    first_faces = time.perf_counter() - start
    vertices = mesh.vertices
    world = incise.World(mesh)
    copy_vertices = timed(lambda: np.array(vertices, copy=True))
    copy_faces = timed(lambda: np.array(faces, copy=True))
    return {"vertices": len(vertices), "faces": len(faces),
            "mesh_vertices_view_us": 1e6 * timed(lambda: mesh.vertices),
            "mesh_faces_first_ms": 1e3 * first_faces,
            "mesh_faces_view_us": 1e6 * timed(lambda: mesh.faces),
            "world_vertices_copy_ms": 1e3 * timed(lambda: world.vertices),
            "world_faces_copy_ms": 1e3 * timed(lambda: world.faces),
            "numpy_copy_vertices_ms": 1e3 * copy_vertices, "numpy_copy_faces_ms": 1e3 * copy_faces,
            "vertices_GB_per_s_world": vertices.nbytes / 1e9 / timed(lambda: world.vertices),
            "vertices_GB_per_s_numpy": vertices.nbytes / 1e9 / copy_vertices}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--subdivide", type=int, default=5)
    args = parser.parse_args()
    scenario = incise.shipped("bunny-straight.json")
    result = {
        "date": time.strftime("%Y-%m-%d"),
        "machine": {"cpu": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
                    "python": platform.python_version(), "numpy": np.__version__, "incise": incise.__version__},
        "step": step_overhead(scenario, args.repeats),
        "idle_step": idle_call(scenario, 20000),
        "arrays": arrays(args.subdivide),
    }
    with open("/proc/cpuinfo") as f:
        names = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
    if names:
        result["machine"]["cpu"] = names[0]
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
