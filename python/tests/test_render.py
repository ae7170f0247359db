"""TCA-MESH and CBA behind the common servo interface: step vs replay tick for tick, NaN input
gives zero force, the stroke equals `inhap tca stroke`, and replay checks its arrays."""
import numpy as np
import pytest

import inhap
from conftest import read_table


def press_path(n=3000):
    """A probe path (t s, p mm) that descends onto the map's bump, slides and lifts."""
    t = np.arange(n, dtype=np.float64) * 1e-3
    s = np.linspace(0, 1, n)
    x = 8.0 + 16.0 * s
    z = 4.0 - 5.5 * np.sin(np.pi * s)
    p = np.ascontiguousarray(np.column_stack([x, np.full(n, 16.0), z]))
    return t, p


@pytest.mark.parametrize("algorithm", ["tca", "cba"])
def test_step_equals_replay(map_mesh, algorithm):
    model = inhap.MeshModel(map_mesh[0])
    r = getattr(inhap.Renderer, algorithm)(model)
    assert r.name == ("tca-mesh" if algorithm == "tca" else "cba")
    t, p = press_path()
    out = r.replay(t, p)
    assert out["force"].shape == (len(t), 3) and out["contact"].dtype == np.bool_
    assert out["contact"].sum() > 500
    assert np.abs(out["force"]).max() > 0.5
    r.reset()
    forces = np.array([r.step(t[i], p[i]).force for i in range(len(t))])
    np.testing.assert_array_equal(forces, out["force"])
    # A second renderer on the same model continues from where step left off when reset=False.
    r2 = getattr(inhap.Renderer, algorithm)(model)
    a = r2.replay(t[:1000], p[:1000])
    b = r2.replay(t[1000:], p[1000:], reset=False)
    np.testing.assert_array_equal(np.vstack([a["force"], b["force"]]), out["force"])


def test_nan_gives_zero_force(map_mesh):
    r = inhap.Renderer.tca(inhap.MeshModel(map_mesh[0]))
    t, p = press_path()
    p[1500] = np.nan
    p[1501, 1] = np.nan
    out = r.replay(t, p)
    assert np.abs(out["force"][1499]).max() > 0  # in contact before
    np.testing.assert_array_equal(out["force"][1500:1502], 0.0)
    assert not out["contact"][1500:1502].any()
    r.reset()
    for i in range(1500):
        r.step(t[i], p[i])
    o = r.step(t[1500], [np.nan, 16.0, 0.0])
    assert o.force.tolist() == [0.0, 0.0, 0.0] and not o.contact
    assert np.all(np.isfinite(out["force"]))


def test_replay_rejects_copies(map_mesh):
    r = inhap.Renderer.cba(inhap.MeshModel(map_mesh[0]))
    t, p = press_path(100)
    with pytest.raises(TypeError, match="C-contiguous"):
        r.replay(t, np.asfortranarray(p))
    with pytest.raises(TypeError, match="float64"):
        r.replay(t, p.astype(np.float32))
    with pytest.raises(TypeError, match="shape"):
        r.replay(t, p[:50])
    with pytest.raises(TypeError, match="shape"):
        r.replay(t, p[:, :2].copy())


def test_stroke_equals_cli(map_mesh, cli, tmp_path):
    _, path = map_mesh
    out = tmp_path / "stroke.csv"
    cli("tca", "stroke", "--mesh", path, "--algorithm", "tca", "--from", "6,16", "--to", "26,16",
        "--force", 1.5, "--speed", 40, "--out", out)
    c = read_table(out)
    s = inhap.simulate_stroke(inhap.MeshModel(inhap.read_mesh(path)), "tca", (6, 16), (26, 16),
                              force=1.5, speed=40)
    np.testing.assert_array_equal(s["t"], c["t"])
    np.testing.assert_array_equal(s["hip"], np.column_stack([c["px"], c["py"], c["pz"]]))
    np.testing.assert_array_equal(s["force"], np.column_stack([c["fx"], c["fy"], c["fz"]]))
    np.testing.assert_array_equal(s["s"], c["s"])
    with pytest.raises(ValueError, match="tca or cba"):
        inhap.simulate_stroke(inhap.MeshModel(inhap.read_mesh(path)), "xyz", (6, 16), (26, 16))
