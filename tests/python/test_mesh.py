"""incise.Mesh and load_mesh: the arrays' shapes, dtypes and ownership, and bad meshes refused."""
import gc
import sys

import numpy as np
import pytest

import incise
from conftest import fnv1a_hash


@pytest.fixture(scope="module")
def bunny(scenarios):
    return incise.load_mesh(scenarios / "meshes" / "bunny.obj", scale=0.01)


def test_load_mesh_gives_vertices_n_by_3_float64_and_faces_m_by_3_int64(bunny):
    assert bunny.vertices.shape == (bunny.summary["vertices"], 3) and bunny.vertices.dtype == np.float64
    assert bunny.faces.shape == (bunny.summary["faces"], 3) and bunny.faces.dtype == np.int64
    assert bunny.face_kinds.shape == (len(bunny.faces),) and bunny.face_kinds.dtype == np.uint8
    assert bunny.wall.dtype == np.bool_ and not bunny.wall.any()
    assert bunny.vertex_kinds.dtype == np.uint8 and len(bunny.vertex_kinds) == len(bunny.vertices)
    assert bunny.faces.min() == 0 and bunny.faces.max() == len(bunny.vertices) - 1
    assert bunny.summary["closed_two_manifold"] and bunny.summary["euler_characteristic"] == 2


def test_the_scale_is_applied_in_metres(scenarios, bunny):
    raw = incise.load_mesh(scenarios / "meshes" / "bunny.obj")
    assert np.array_equal(raw.vertices * 0.01, bunny.vertices)
    assert np.ptp(bunny.vertices, axis=0).max() < 0.2  # a bunny ~15 cm long


def test_vertices_and_faces_are_read_only_views_that_keep_the_mesh_alive(scenarios):
    mesh = incise.load_mesh(scenarios / "meshes" / "bunny.obj", scale=0.01)
    first, again = mesh.vertices, mesh.vertices
    assert np.shares_memory(first, again), "two reads of vertices are views of the same memory"
    assert not first.flags.writeable and not mesh.faces.flags.writeable and not first.flags.owndata
    with pytest.raises(ValueError):
        first[0, 0] = 1.0
    faces = mesh.faces
    expected = faces.copy()
    refs = sys.getrefcount(mesh)
    del mesh
    gc.collect()
    assert np.array_equal(faces, expected) and np.isfinite(first).all(), "the views outlive the name"
    assert refs >= 3  # the views hold references to the mesh


def test_wall_and_vertex_kinds_are_new_arrays_each_time(bunny):
    a, b = bunny.wall, bunny.wall
    assert not np.shares_memory(a, b) and a.flags.owndata and a.flags.writeable


def test_the_arrays_are_the_mesh_the_geometry_hash_describes(bunny):
    assert fnv1a_hash(bunny.vertices, bunny.faces, bunny.face_kinds) == bunny.geometry_hash


def test_subdivide_multiplies_the_faces_by_four(scenarios, bunny):
    finer = incise.load_mesh(scenarios / "meshes" / "bunny.obj", scale=0.01, subdivide=1)
    assert len(finer.faces) == 4 * len(bunny.faces)


def test_a_mesh_from_arrays_is_the_same_mesh(bunny):
    again = incise.Mesh.from_arrays(bunny.vertices, bunny.faces)
    assert again.geometry_hash == bunny.geometry_hash


def test_bad_meshes_raise_input_error_naming_what_and_where(tmp_path, bunny):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(incise.InputError, match=r"bad\.obj:4: face index 9 out of range"):
        incise.load_mesh(bad)
    with pytest.raises(incise.InputError, match="no-such.obj"):
        incise.load_mesh(tmp_path / "no-such.obj")
    open_faces = np.asarray(bunny.faces)[:-1]
    with pytest.raises(incise.InputError, match="not a closed two-manifold"):
        incise.Mesh.from_arrays(bunny.vertices, open_faces)
    with pytest.raises(incise.InputError, match="face 0: vertex index -1"):
        incise.Mesh.from_arrays(bunny.vertices, np.vstack([[-1, 0, 1], bunny.faces]))
    with pytest.raises(ValueError, match="N x 3"):
        incise.Mesh.from_arrays(bunny.vertices[:, :2], bunny.faces)
    assert issubclass(incise.InputError, ValueError)
    with pytest.raises(ValueError, match="subdivide"):
        incise.load_mesh(bad, subdivide=7)


def test_save_obj_writes_what_the_mesh_holds(tmp_path, bunny):
    bunny.save_obj(tmp_path / "bunny.obj")
    again = incise.load_mesh(tmp_path / "bunny.obj")
    assert again.geometry_hash == bunny.geometry_hash


def planar_map(x_m):
    """A planar texture map of positions in metres (..., 3) -> (..., 2): linear, so exact wherever a cut
    interpolates it."""
    x, y, z = x_m[..., 0], x_m[..., 1], x_m[..., 2]
    return np.stack([20.0 * x + 3.0 * z + 0.5, 20.0 * y - 5.0 * z + 0.25], axis=-1)


@pytest.fixture
def textured_bunny(tmp_path, scenarios):
    """The bunny (in metres) with the planar map as its `vt`s and two materials, half its faces each."""
    bunny = incise.load_mesh(scenarios / "meshes" / "bunny.obj", scale=0.01)
    uv = planar_map(bunny.vertices)
    lines = ["mtllib textured.mtl"]
    lines += ["v %r %r %r" % tuple(p) for p in bunny.vertices]
    lines += ["vt %r %r" % tuple(c) for c in uv]
    half = len(bunny.faces) // 2
    for i, face in enumerate(bunny.faces):
        if i in (0, half):
            lines.append("usemtl " + ("skin" if i == 0 else "skin_dark"))
        lines.append("f " + " ".join(f"{v + 1}/{v + 1}" for v in face))
    (tmp_path / "textured.obj").write_text("\n".join(lines) + "\n")
    (tmp_path / "textured.mtl").write_text("newmtl skin\nKd 0.9 0.7 0.6\n\nnewmtl skin_dark\nKd 0.7 0.5 0.4\n")
    return tmp_path / "textured.obj"


def test_a_mesh_without_texture_coordinates_or_materials_has_none(bunny):
    assert bunny.texcoords is None and bunny.face_materials is None and bunny.materials == []


def test_texture_coordinates_and_materials_are_read_per_face_corner(textured_bunny):
    mesh = incise.load_mesh(textured_bunny)
    uv = mesh.texcoords
    assert uv.shape == (len(mesh.faces), 3, 2) and uv.dtype == np.float64
    np.testing.assert_allclose(uv, planar_map(mesh.vertices[mesh.faces]), rtol=0, atol=1e-12)
    assert mesh.materials == ["skin", "skin_dark"]
    half = len(mesh.faces) // 2
    assert mesh.face_materials.dtype == np.int32
    assert (mesh.face_materials[:half] == 0).all() and (mesh.face_materials[half:] == 1).all()


def test_a_cut_keeps_them_exact_on_the_skin_and_maps_the_walls(textured_bunny):
    loaded = incise.load_mesh(textured_bunny)
    cut = incise.cut(mesh=textured_bunny, scale=1.0, subdivide=0)
    assert cut.ok, cut.failure
    mesh, n = cut.mesh, len(loaded.vertices)
    uv, kinds = mesh.texcoords, mesh.face_kinds
    assert uv.shape == (len(mesh.faces), 3, 2) and np.isfinite(uv).all()
    # Skin faces whose corners the cut did not move: their coordinates are the map's at those corners.
    unmoved = np.zeros(len(mesh.vertices), dtype=bool)
    unmoved[:n] = (mesh.vertices[:n] == loaded.vertices).all(axis=1)
    still = (kinds != 2) & unmoved[mesh.faces].all(axis=1)
    assert still.sum() > 0.9 * len(loaded.faces)
    np.testing.assert_allclose(uv[still], planar_map(mesh.vertices[mesh.faces[still]]), rtol=0, atol=1e-9)
    # Split faces interpolate the map; walls have their own coordinates (metres along the stroke and down).
    assert (kinds == 1).any() and (kinds == 2).any()
    assert mesh.materials == ["skin", "skin_dark"] and set(mesh.face_materials[kinds != 2]) == {0, 1}
    assert (mesh.face_materials[kinds == 2] == -1).all()
