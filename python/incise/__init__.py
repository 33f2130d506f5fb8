"""incise: real-time surgical cutting by discontinuous free-form deformation, from Python.

A scalpel cuts a soft-tissue surface (a closed triangle mesh, in metres): a trivariate B-spline deformation
into which a discontinuity is inserted and grown along the stroke (Schein & Elber's DFFD). This package runs
the same code as the `incise` command-line tool, so the same options give the same bytes:

    load_mesh(path, scale, subdivide)     a mesh file as an incise.Mesh (numpy arrays)
    cut(mesh=..., start=..., length=...)  one stroke across a mesh, as `incise cut`: an incise.Cut
    replay(scenario, fast=True)           a scenario's poses through the simulation, as `incise replay`
    score(scenario, traces)               recorded sessions scored, as `incise score`: a list of dicts
    score_summary(lines)                  the summary line `incise score` prints after them
    World(mesh, **options)                a world you step yourself: poses in, force and contact out
    World.from_scenario(path)             ... as a scenario file describes it, with its poses
    read_trace(path), read_jigsaws(path)  recorded motion as pose arrays
    data_dir(), shipped(name)             the shipped scenarios, meshes and traces

Arrays: vertices N x 3 float64 (metres), faces M x 3 int64 (counter-clockwise seen from outside),
face_kinds M uint8 (0 skin, 1 split skin, 2 wound wall), wall M bool; texcoords M x 3 x 2 float64 and
face_materials M int32 for a textured mesh (None otherwise); poses N x 10 float64 in a trace's
columns: time_s, tip x y z (metres), orientation w x y z, buttons, pressure (NaN: no sensor). A Mesh's
vertices and faces are read-only views (no copy); a World's arrays are copies (its mesh changes on).
Errors: incise.InputError (a ValueError) for a file, mesh, scenario or trace incise refuses, its message
naming the file and line, key path or element; ValueError and TypeError for bad arguments.
The long calls release the GIL; a World serves one thread at a time.
"""

import json
import os
import pathlib
import warnings

from . import _arguments, _incise, _paths
from ._incise import InputError, Mesh, Step, World, __version__, load_mesh, read_jigsaws, read_trace

__all__ = [
    "Cut",
    "InputError",
    "Mesh",
    "Replay",
    "Step",
    "World",
    "cut",
    "data_dir",
    "load_mesh",
    "read_jigsaws",
    "read_trace",
    "replay",
    "score",
    "score_summary",
    "shipped",
    "__version__",
]


def data_dir():
    """The folder of the shipped scenarios (with their meshes/, traces/, hid/), a pathlib.Path.

    Searched in order: the INCISE_SCENARIOS environment variable; the installed copy
    (<prefix>/share/incise/scenarios, found from this package's place under the prefix); the source tree
    the package was built from. Raises FileNotFoundError listing the folders tried.
    """
    here = pathlib.Path(__file__).resolve().parent
    tried = []
    for candidate in (os.environ.get("INCISE_SCENARIOS"), here / _paths.SCENARIOS_FROM_PACKAGE,
                      _paths.SCENARIOS_SOURCE):
        if not candidate:
            continue
        folder = pathlib.Path(candidate).resolve()
        if (folder / "bunny-straight.json").is_file():
            return folder
        tried.append(str(folder))
    raise FileNotFoundError("incise: no shipped scenarios in " + ", ".join(tried) + " (set INCISE_SCENARIOS)")


def shipped(name):
    """data_dir() / name as a str, e.g. shipped("pad-straight.json"), shipped("meshes/bunny.obj")."""
    return str(data_dir() / name)


class _MeshResult:
    """What a cut and a replay share: their mesh's arrays (see incise.Mesh) and its OBJ file."""

    vertices = property(lambda self: self.mesh.vertices, doc="N x 3 float64, metres (a read-only view).")
    faces = property(lambda self: self.mesh.faces, doc="M x 3 int64 (a read-only view).")
    face_kinds = property(lambda self: self.mesh.face_kinds, doc="M uint8: 0 skin, 1 split, 2 wall (a view).")
    wall = property(lambda self: self.mesh.wall, doc="M bool: wall faces of the wound (a copy).")

    def save_obj(self, path):
        """The mesh as OBJ: the bytes the CLI writes to cut.obj (walls in the group `wall`)."""
        self.mesh.save_obj(_arguments.path(path, "path"))


class Cut(_MeshResult):
    """A stroke cut across a mesh (incise.cut): the cut mesh and summary.json's document.

    mesh      the cut mesh (an incise.Mesh: its arrays are read-only views)
    summary   the dict `incise cut` writes to summary.json: the options, edges split, seam vertices,
              per incision figures, the mesh's summary, per-sample timings, failure
    ok        the mesh is a closed two-manifold with its Euler characteristic, and the cut did not fail
    failure   why the cut failed ("" when it did not)
    vertices, faces, face_kinds, wall: the mesh's (see incise.Mesh)
    """

    def __init__(self, mesh, summary, ok, failure):
        self.mesh = mesh
        self.summary = summary
        self.ok = ok
        self.failure = failure

    def __repr__(self):
        return f"<incise.Cut: {self.mesh!r}, {'ok' if self.ok else 'failed: ' + self.failure}>"


_CUT_OPTIONS = ("scale", "subdivide", "start", "direction", "length", "bend", "speed", "depth", "opening",
                "alpha", "beta", "spacing", "refine", "refine_edge")


def cut(mesh=None, *, scale=None, subdivide=None, start=None, direction=None, length=None, bend=None, speed=None,
        depth=None, opening=None, alpha=None, beta=None, spacing=None, refine=None, refine_edge=None):
    """One scalpel stroke across a tissue surface, as `incise cut` cuts it; returns an incise.Cut.

    The mesh file (OBJ, PLY, OFF, STL) is scaled to metres and Loop-subdivided; a stroke is drawn along a
    path over it (rays down -y onto the surface, sampled at 1 kHz) and cut sample by sample. The options
    are `incise cut`'s, with its defaults (None: the default):
      mesh        the mesh file (default: the shipped bunny, {mesh})
      scale       metres per file unit ({scale})          subdivide  Loop subdivisions, 0..5 ({subdivide})
      start       the path's first point, metres ({start})
      direction   the path's direction ({direction})
      length      the stroke's length, metres ({length})  bend       sideways bulge at the middle, m ({bend})
      speed       blade speed, m/s ({speed})              depth      blade depth, m ({depth})
      opening     the wound's width, m ({opening})        alpha      lattice spacing across, m ({alpha})
      beta        lattice spacing along the normal ({beta}) spacing  stroke resampling step, m ({spacing})
      refine      'linear', 'pn' or 'off' ({refine})      refine_edge longest edge kept, m; 0: automatic ({refine_edge})
    Raises incise.InputError for a bad mesh file (file:line), ValueError for bad options or a path whose
    first ray misses the surface. The cut mesh has the bytes `incise cut` writes (Cut.save_obj). Releases
    the GIL while it cuts.
    """
    options = {}
    given = dict(scale=scale, subdivide=subdivide, start=start, direction=direction, length=length, bend=bend,
                 speed=speed, depth=depth, opening=opening, alpha=alpha, beta=beta, spacing=spacing, refine=refine,
                 refine_edge=refine_edge)
    for key, value in given.items():
        if value is None:
            continue
        if key in ("start", "direction"):
            options[key] = _arguments.vector3(value, key)
        elif key == "refine":
            if value not in ("linear", "pn", "off"):
                raise ValueError(f"refine: expected 'linear', 'pn' or 'off', got {value!r}")
            options[key] = value
        elif key == "subdivide":
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 5:
                raise ValueError(f"subdivide: expected an integer in 0..5, got {value!r}")
            options[key] = value
        else:
            options[key] = _arguments.number(value, key)
    path = _arguments.existing_file(shipped("meshes/bunny.obj") if mesh is None else mesh, "mesh")
    result, summary, ok, failure = _incise._cut(path, options)
    return Cut(result, json.loads(summary), ok, failure)


def _document_cut_defaults():
    defaults = {key: value for key, value in _incise._cut_defaults().items()}
    defaults["mesh"] = "meshes/bunny.obj"
    cut.__doc__ = cut.__doc__.format(**defaults)


_document_cut_defaults()


class Replay(_MeshResult):
    """A scenario replayed (incise.replay): the cut tissue and report.json's document.

    mesh           the tissue as the replay left it (an incise.Mesh, read-only views)
    report         the dict `incise replay` writes to report.json: frames, poses, incisions, the cut's
                   figures and failure, geometry_hash, the mesh's summary, latency and loop figures, tets
    geometry_hash  report["geometry_hash"]: 16 hex digits, equal for equal meshes
    vertices, faces, face_kinds, wall: the mesh's (see incise.Mesh)
    """

    def __init__(self, mesh, report):
        self.mesh = mesh
        self.report = report

    geometry_hash = property(lambda self: self.report["geometry_hash"], doc="16 hex digits (report.json's).")

    def __repr__(self):
        return f"<incise.Replay {self.report['scenario']}: {self.report['incisions']} incision(s), {self.geometry_hash}>"


def replay(scenario=None, fast=True):
    """A scenario's poses through the simulation, as `incise replay` (default: the shipped bunny-straight.json).

    fast=True runs the frames back to back (`--fast`); fast=False paces them at the scenario's rate on a
    fixed-rate thread (`--realtime`, as long as the trace). Both give the same geometry. Returns an
    incise.Replay whose report is report.json's document (a tet tissue's files are not written). Raises
    incise.InputError naming the file and key or line at fault; a recording's skipped reports come as a
    UserWarning. Releases the GIL while it runs.
    """
    path = _arguments.existing_file(shipped("bunny-straight.json") if scenario is None else scenario, "scenario")
    mesh, report, notes = _incise._replay(path, bool(fast))
    for note in notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    return Replay(mesh, json.loads(report))


def score(scenario, traces):
    """Recorded sessions scored against a scenario, as `incise score`: one dict per trace, in order.

    `traces`: a trace file (CSV), an N x 10 pose array, or a list of them. Each is replayed as
    `incise replay --fast` and measured: time, path, economy, idle time, force, strokes, smoothness, and
    against the scenario's plan the lateral and depth errors and the shares cut within tolerance. A dict is
    the line `incise score` prints: {"trace": the file as given, or "poses[i]" for an array, ...}. Every
    trace is read and checked before any is scored: a file recorded on another tissue, or empty, raises
    incise.InputError or ValueError naming it; a trace without a tissue comment is scored with a
    UserWarning. Releases the GIL while it scores.
    """
    scenario_path = _arguments.existing_file(scenario, "scenario")
    if isinstance(traces, (str, os.PathLike)) or (hasattr(traces, "ndim") and traces.ndim == 2):
        traces = [traces]
    items = []
    for i, trace in enumerate(traces):
        if isinstance(trace, (str, os.PathLike)):
            items.append((os.fspath(trace), _arguments.path(trace, f"traces[{i}]")))
        else:
            items.append((f"poses[{i}]", _arguments.poses(trace, f"traces[{i}]")))
    if not items:
        raise ValueError("traces: no trace to score")
    lines, notes = _incise._score(scenario_path, items)
    for note in notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    return [json.loads(line) for line in lines]


def score_summary(lines):
    """The summary `incise score` prints after the traces' lines: {"summary": {"traces": n, "mean": {...}}},
    the means of the headline figures (and of the plan's) over the dicts incise.score returned."""
    return json.loads(_incise._score_summary([json.dumps(line) for line in lines]))
