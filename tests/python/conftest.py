"""What the module's tests share: the package, the CLI it must agree with, the shipped scenarios, and the
CLI's outputs made once per session."""
import json
import os
import pathlib
import subprocess

import pytest


@pytest.fixture(scope="session")
def cli():
    """The `incise` tool of the same build (INCISE_CLI)."""
    path = os.environ.get("INCISE_CLI")
    if not path:
        pytest.fail("INCISE_CLI is not set (CTest sets it to the build's incise)")
    return path


@pytest.fixture(scope="session")
def scenarios():
    return pathlib.Path(os.environ["INCISE_SCENARIOS"])


def run_cli(cli, *args, cwd=None):
    """Runs the CLI; its stdout. A non-zero exit fails the test with its stderr."""
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    if done.returncode != 0:
        pytest.fail(f"incise {' '.join(map(str, args))}: exit {done.returncode}: {done.stderr}")
    return done.stdout


@pytest.fixture(scope="session")
def cli_replays(cli, scenarios, tmp_path_factory):
    """report.json of `incise replay --fast` per scenario name, made on first use."""
    made = {}

    def replay(name):
        if name not in made:
            out = tmp_path_factory.mktemp("replay-" + name)
            run_cli(cli, "replay", scenarios / f"{name}.json", "--fast", "--out", out)
            made[name] = (json.loads((out / "report.json").read_text()), out / "cut.obj")
        return made[name]

    return replay


def fnv1a_hash(vertices, faces, face_kinds):
    """mesh_hash.h's FNV-1a over the arrays (positions' bytes, then per face its int32 indices and uint8
    kind), in Python: the arrays hold exactly the mesh the C++ hash describes."""
    import numpy as np

    h = 1469598103934665603
    mask = (1 << 64) - 1
    data = bytearray(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
    per_face = np.zeros(len(faces), dtype=[("v", "<i4", 3), ("k", "u1")])
    per_face["v"] = faces
    per_face["k"] = face_kinds
    data += per_face.tobytes()
    for byte in data:
        h = ((h ^ byte) * 1099511628211) & mask
    return f"{h:016x}"
