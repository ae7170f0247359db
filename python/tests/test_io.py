"""Recordings, meshes and maps: zero-copy views, in-place writes seen by the library, and
TypeError (never a silent copy) for a wrong dtype, shape or memory order."""
import numpy as np
import pytest

import inhap


def small_recording(n=50):
    t = np.arange(n, dtype=np.float64) * 1e-3
    p = np.column_stack([np.linspace(0, 1, n), np.zeros(n), np.full(n, 2.0)])
    f = np.zeros((n, 3))
    f[:, 2] = np.linspace(0, 3, n)
    return inhap.Recording(t, p, f, {"qx": p[:, 0].copy()})


def test_version():
    assert inhap.__version__ == "0.1.0"


def test_recording_views_share_memory(tmp_path):
    rec = small_recording()
    assert rec.columns == ["t", "px", "py", "pz", "fx", "fy", "fz", "qx"]
    p = rec.p
    assert p.shape == (50, 3) and p.dtype == np.float64
    assert np.shares_memory(rec["px"], p) and np.shares_memory(rec["fz"], rec.f)
    assert np.shares_memory(rec.p, rec.p)  # a view of the same storage each time
    # An in-place write through the view is what the library writes to the file.
    p[3, 0] = 123.25
    rec["qx"][4] = -7.5
    path = tmp_path / "r.csv"
    rec.write(str(path))
    back = inhap.read_recording(str(path))
    assert back.p[3, 0] == 123.25 and back["qx"][4] == -7.5
    np.testing.assert_array_equal(back.t, rec.t)
    np.testing.assert_array_equal(back.f, rec.f)


def test_recording_view_outlives_object():
    p = small_recording().p  # the array keeps the recording alive
    assert p[10, 2] == 2.0


def test_recording_set_column_and_errors(tmp_path):
    rec = small_recording()
    rec["contact"] = np.ones(50)
    assert "contact" in rec and rec["contact"].sum() == 50
    with pytest.raises(KeyError):
        rec["nope"]
    with pytest.raises(TypeError, match="float64"):
        rec["contact"] = np.ones(50, dtype=np.float32)
    bad = tmp_path / "bad.csv"
    bad.write_text("t,px,py,pz,fx,fy,fz\n0,0,0,0,0,0,0\n0,1,2\n")
    with pytest.raises(inhap.ParseError, match="bad.csv:3"):
        inhap.read_recording(str(bad))
    with pytest.raises(inhap.Error):
        inhap.read_recording(str(tmp_path / "missing.csv"))


@pytest.mark.parametrize(
    "arr, message",
    [
        (np.zeros((10, 3), dtype=np.float32), "float64"),
        (np.zeros((10, 3), dtype=np.int64), "float64"),
        (np.zeros((10, 2)), "shape"),
        (np.zeros(30), "shape"),
        (np.asfortranarray(np.zeros((10, 3))), "C-contiguous"),
        (np.zeros((10, 6))[:, ::2], "C-contiguous"),
        ([[0.0, 0.0, 0.0]] * 10, "numpy array"),
    ],
)
def test_wrong_arrays_raise_type_error(arr, message):
    t = np.arange(10, dtype=np.float64)
    with pytest.raises(TypeError, match=message):
        inhap.Recording(t, arr, np.zeros((10, 3)))
    with pytest.raises(TypeError, match=message):
        inhap.detect_contacts(t, arr, np.zeros((10, 3)))


def test_mesh_views_and_roundtrip(tmp_path, map_mesh):
    mesh, _ = map_mesh
    assert mesh.vertices.shape == (33 * 33, 3)
    assert mesh.faces.shape == (2 * 32 * 32, 3) and mesh.faces.dtype == np.int32
    k = mesh.properties["stiffness"]
    assert k.shape == (33 * 33,)
    assert np.shares_memory(mesh.vertices, mesh.vertices)
    # In-place writes reach the mesh the library writes.
    mesh2 = inhap.Mesh(mesh.vertices.copy(), mesh.faces.copy(), {"stiffness": k.copy()})
    mesh2.vertices[0, 2] = -4.5
    mesh2.properties["stiffness"][1] = 0.125
    for name in ("m.ply", "m_ascii.ply"):
        path = str(tmp_path / name)
        assert inhap.write_mesh(path, mesh2, ascii=name.endswith("ascii.ply")) == []
        back = inhap.read_mesh(path)
        assert back.vertices[0, 2] == -4.5 and back.properties["stiffness"][1] == 0.125
        np.testing.assert_array_equal(back.faces, mesh2.faces)
    assert inhap.write_mesh(str(tmp_path / "m.obj"), mesh2) == ["stiffness"]
    back = inhap.read_mesh(str(tmp_path / "m.obj"))
    np.testing.assert_allclose(back.vertices, mesh2.vertices)
    with pytest.raises(TypeError, match="int32"):
        inhap.Mesh(mesh.vertices.copy(), mesh.faces.astype(np.int64))


def test_grids_and_points(tmp_path, cli):
    g = tmp_path / "h.csv"
    g.write_text("0,1,2\n3,4,5\n")
    a = inhap.read_grid(str(g))
    np.testing.assert_array_equal(a, [[0, 1, 2], [3, 4, 5]])
    m = inhap.grid_to_mesh(a, 0.5)
    assert m.vertices.shape == (6, 3) and m.faces.shape == (4, 3)
    assert m.vertices[5].tolist() == [1.0, 0.5, 5.0]
    with pytest.raises(TypeError):
        inhap.grid_to_mesh(np.asfortranarray(a), 0.5)
    # The CLI's mesh heightmap gives the same mesh.
    out = tmp_path / "h.ply"
    cli("mesh", "heightmap", g, "--spacing", 0.5, "--out", out)
    c = inhap.read_mesh(str(out))
    np.testing.assert_array_equal(c.vertices, m.vertices)
    np.testing.assert_array_equal(c.faces, m.faces)
    pts = inhap.read_points(str(out))
    np.testing.assert_array_equal(pts.points, m.vertices)
