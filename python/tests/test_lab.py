"""Tapping and the `inhap eval` experiments from Python give the program's numbers for the same
seed: contact points, reconstruction, comparison, `eval contacts` and `eval forces --quick`."""
import numpy as np
import pytest

import inhap
from conftest import read_table


@pytest.fixture(scope="module")
def taps(tmp_path_factory, cli):
    d = tmp_path_factory.mktemp("taps")
    path = d / "taps.csv"
    cli("lab", "record", "--scene", "silicone-hemisphere", "--operator", "tap", "--probe", "tip",
        "--seconds", 40, "--seed", 1, "--out", path)
    return d, str(path)


def table(path):
    return read_table(path)


def test_contacts_equal_cli(taps, cli):
    d, path = taps
    rec = inhap.read_recording(path)
    for method in ("estimate", "threshold"):
        cli("shape", "contacts", path, "--method", method, "--out", d / "c.ply", "--csv",
            d / "c.csv")
        c = table(d / "c.csv")
        got = inhap.contacts_from_recording(rec, method=method)
        assert len(got) == len(c["tap"]) > 10
        np.testing.assert_array_equal(got.point, np.column_stack([c["x"], c["y"], c["z"]]))
        np.testing.assert_array_equal(got.direction, np.column_stack([c["dx"], c["dy"], c["dz"]]))
        np.testing.assert_array_equal(got.peak_force, c["peak_force"])
        np.testing.assert_array_equal(got.t_contact, c["t_contact"])
    # detect_contacts on arrays (the recorded force) equals --force recorded
    cli("shape", "contacts", path, "--force", "recorded", "--out", d / "r.ply", "--csv",
        d / "r.csv")
    c = table(d / "r.csv")
    got = inhap.detect_contacts(rec.t, np.ascontiguousarray(rec.p), rec.f)
    np.testing.assert_array_equal(got.t_contact, c["t_contact"])


def test_reconstruct_and_compare_equal_cli(taps, cli, cli_json):
    d, path = taps
    cli("shape", "contacts", path, "--out", d / "pts.ply")
    cli("shape", "reconstruct", d / "pts.ply", "--out", d / "cli_mesh.ply")
    pts = inhap.read_points(str(d / "pts.ply"))
    mesh, summary = inhap.reconstruct_surface(pts.points, pts.directions)
    assert "alpha" in summary
    ref = inhap.read_mesh(str(d / "cli_mesh.ply"))
    np.testing.assert_array_equal(mesh.vertices, ref.vertices)
    np.testing.assert_array_equal(mesh.faces, ref.faces)
    mesh.write(str(d / "py_mesh.ply"))
    cj = cli_json("shape", "compare", d / "py_mesh.ply", d / "cli_mesh.ply")
    pj = inhap.compare_meshes(mesh, ref, a_name=str(d / "py_mesh.ply"),
                              b_name=str(d / "cli_mesh.ply"))
    assert pj == cj
    assert pj["a_to_b"]["max_mm"] < 1e-9  # the same mesh


def test_eval_contacts_equal_cli(cli_json):
    c = cli_json("eval", "contacts", "--taps", 12, "--seed", 4)
    p = inhap.eval_contacts(taps=12, seed=4, progress=False)
    assert p == c


def is_timing(key):
    """Wall-clock fields of the `eval forces` report (training s, palpation s, step us)."""
    return key.endswith("train_s") or key in ("palpation_s", "step_us")


def strip_timing(x):
    """The report without its wall-clock fields (they differ run to run)."""
    if isinstance(x, dict):
        return {k: strip_timing(v) for k, v in x.items() if not is_timing(k)}
    if isinstance(x, list):
        return [strip_timing(v) for v in x]
    return x


def test_eval_forces_quick_equal_cli(cli_json):
    c = cli_json("eval", "forces", "--quick", "--scenes", "planar")
    p = inhap.eval_forces(scenes=["planar"], quick=True, progress=False)
    assert strip_timing(p) == strip_timing(c)
    planar = p["objects"][0]
    assert planar["train_s"] > 0 and len(strip_timing(planar)) >= len(planar) - 4


def test_fit_knee_finds_the_break():
    t = np.arange(100, dtype=np.float64) * 1e-3
    tc = 0.0637
    f = np.where(t < tc, 0.01, 0.01 + 40.0 * (t - tc))
    k = inhap.fit_knee(t, f)
    assert k["valid"] and abs(k["tc"] - tc) < 1e-6 and k["sse"] < 1e-12
    assert t[k["index"]] <= k["tc"] < t[k["index"] + 1]
    with pytest.raises(TypeError):
        inhap.fit_knee(t, f.astype(np.float32))
    assert not inhap.fit_knee(t[:3], f[:3])["valid"]


def test_eval_sys_and_tca_equal_cli(cli_json):
    """`eval sys --quick` and `eval tca --quick` as dicts: the program's report but for its
    wall-clock and CPU times (palpation times, servo-step latencies)."""
    c = cli_json("eval", "sys", "--quick", "--scenes", "planar")
    p = inhap.eval_sys(scenes=["planar"], quick=True, progress=False)
    for obj in (c["objects"][0], p["objects"][0]):
        for key in [k for k in obj if k.startswith("palpation_") and ("cpu" in k or "wall" in k)]:
            assert obj.pop(key) > 0
    assert p == c
    c = cli_json("eval", "tca", "--quick", "--participants", 2, "--trials", 1)
    p = inhap.eval_tca(quick=True, participants=2, trials=1, progress=False)
    assert p.pop("step_us")["tca"]["p50"] > 0 and c.pop("step_us")
    assert p == c


def test_lab_scene_file_equals_cli(tmp_path, cli):
    assert "planar" in inhap.lab_scenes() and "dome" in inhap.lab_scenes_table()
    cli("lab", "scene", "dome", "--out", tmp_path / "cli.json")
    inhap.lab_scene("dome", str(tmp_path / "py.json"))
    assert (tmp_path / "cli.json").read_bytes() == (tmp_path / "py.json").read_bytes()
    a = inhap.lab_record(scene_file=str(tmp_path / "py.json"), seconds=2, seed=7, progress=False)
    b = inhap.lab_record(scene="dome", seconds=2, seed=7, progress=False)
    np.testing.assert_array_equal(a.recording.f, b.recording.f)
    with pytest.raises(inhap.Error):
        inhap.lab_record(scene="no-such-scene", seconds=1, progress=False)


def test_eval_shape_equal_cli(cli_json):
    c = cli_json("eval", "shape", "--quick", "--objects", "foam-ball", "--taps", 60)
    p = inhap.eval_shape(objects=["foam-ball"], taps=60, quick=True, progress=False)
    assert p == c
    with pytest.raises(inhap.Error, match="bunny"):
        inhap.eval_shape(objects=["bunny"], progress=False)


def test_lab_record_rate_equals_cli(tmp_path, cli):
    """A logger slower than the 1 kHz servo (lab record --rate): the same rows and truth."""
    cli("lab", "record", "--scene", "planar", "--seconds", 3, "--seed", 2, "--rate", 66, "--out",
        tmp_path / "cli.csv")
    lab = inhap.lab_record(scene="planar", seconds=3, seed=2, rate=66, out=str(tmp_path / "py.csv"),
                           progress=False)
    assert 150 < len(lab.recording) < 250
    for suffix in (".csv", ".truth.csv"):
        assert (tmp_path / ("cli" + suffix)).read_bytes() == (tmp_path / ("py" + suffix)).read_bytes()
