"""The force model pipelines in memory give the program's numbers: training on an
inhap.Recording (the proxy estimated when it has no proxy columns, as `model train`), `model
eval` and `model render` of a model object on a recording object, `eval recordings`."""
import json

import numpy as np
import pytest

import inhap
from conftest import read_table

TRAIN_FLAGS = dict(centers=60, seed=3)  # else the defaults of `model train` (preset 'best')


@pytest.fixture(scope="module")
def lab(tmp_path_factory, cli):
    """Two lab recordings without proxy columns (a real rig's t, p, f) and the CLI's model."""
    d = tmp_path_factory.mktemp("memory")
    for name, seconds, seed in (("train", 25, 1), ("test", 12, 2)):
        cli("lab", "record", "--scene", "planar", "--seconds", seconds, "--seed", seed, "--out",
            d / f"{name}.csv")
    cli("model", "train", "--recording", d / "train.csv", "--out", d / "cli_model.json",
        "--centers", 60, "--seed", 3)
    return d


def without_run_fields(model_json):
    """A model file's content without what differs between two runs or two file names."""
    j = json.loads(json.dumps(model_json))
    j["train"].pop("seconds")
    j.pop("references", None)
    return j


def test_train_in_memory_equals_the_program(lab, tmp_path):
    rec = inhap.read_recording(str(lab / "train.csv"))
    assert "qx" not in rec  # no proxy columns: estimated
    m = inhap.train_force_model(rec, progress=False, **TRAIN_FLAGS)
    assert m.estimated and m.path == ""
    assert any("estimated" in n for n in m.notes)
    cli_model = inhap.load_force_model(str(lab / "cli_model.json"))
    assert without_run_fields(m.json) == without_run_fields(cli_model.json)
    # The same forces, bit for bit, on random inputs near the surface.
    rng = np.random.default_rng(1)
    p = np.ascontiguousarray(rng.uniform(-20, 20, (500, 3)))
    q = np.ascontiguousarray(p + rng.normal(0, 1, (500, 3)))
    v = np.ascontiguousarray(rng.normal(0, 5, (500, 3)))
    n = np.tile([0.0, 0.0, 1.0], (500, 1))
    np.testing.assert_array_equal(m.force(p, v, q, n), cli_model.force(p, v, q, n))
    # save() writes what `model train --out` writes: the estimated surface, yield surfaces and
    # coverage files byte for byte, the model but for the wall time and the recording named.
    notes = m.save(str(tmp_path / "py_model.json"))
    assert any("surface.ply" in x for x in notes) and m.path == str(tmp_path / "py_model.json")
    for suffix in (".surface.ply", ".sys.json", ".coverage.csv"):
        assert (tmp_path / ("py_model" + suffix)).read_bytes() == \
            (lab / ("cli_model" + suffix)).read_bytes(), suffix
    a = json.loads((lab / "cli_model.json").read_text())
    b = json.loads((tmp_path / "py_model.json").read_text())
    assert a["references"]["recording"]["path"].endswith("train.csv")
    assert b["references"]["recording"] is None  # no training file in memory
    assert without_run_fields(a) == without_run_fields(b)
    # The file path form is the same training.
    f = inhap.train_force_model(str(lab / "train.csv"), progress=False, **TRAIN_FLAGS)
    assert without_run_fields(f.json) == without_run_fields(m.json)


def assert_close(a, b, rel=1e-9, path=""):
    """Equal structure and strings, numbers equal within `rel`."""
    if isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            assert_close(a[k], b[k], rel, f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            assert_close(x, y, rel, f"{path}[{i}]")
    elif isinstance(a, float):
        assert a == pytest.approx(b, rel=rel, abs=1e-12), path
    else:
        assert a == b, path


def test_eval_and_render_in_memory_equal_the_program(lab, cli, cli_json):
    m = inhap.train_force_model(inhap.read_recording(str(lab / "train.csv")), progress=False,
                                **TRAIN_FLAGS)
    test = inhap.read_recording(str(lab / "test.csv"))
    ce = cli_json("model", "eval", "--model", lab / "cli_model.json", "--recording",
                  lab / "test.csv")
    assert "baselines" in ce and ce["proxy_source"] == "estimated"
    # The program's model file as an object, the test recording in memory: the same report.
    fm = inhap.load_force_model(str(lab / "cli_model.json"))
    pe = inhap.evaluate_force_model(fm, test)
    assert pe["recording"] == "recording (in memory)" and pe["model"] == ce["model"]
    assert pe.pop("text") and pe.pop("support_note") and pe.pop("baselines_note")
    pe["recording"] = ce["recording"]
    assert pe == ce
    # The model trained in memory replays with the estimated yield surfaces it keeps; the program
    # reads them back from its sys.json (rebuilt on reading): the same report within 1e-9.
    me = inhap.evaluate_force_model(m, test)
    assert me["model"] == "" and me["recording"] == "recording (in memory)"
    assert me["baselines_note"] == "baselines fitted on the training samples"
    assert me.pop("text") and me.pop("support_note") and me.pop("baselines_note")
    for key in ("model", "recording"):
        me[key] = ce[key]
    me["coverage"]["file"] = ce["coverage"]["file"]
    assert_close(me, ce)
    # The baselines fitted on a training recording given in memory: the program's.
    pt = inhap.evaluate_force_model(fm, test, train=inhap.read_recording(str(lab / "train.csv")))
    assert pt["baselines"] == ce["baselines"]
    # render: the program's CSV, force for force.
    cli("model", "render", "--model", lab / "cli_model.json", "--recording", lab / "test.csv",
        "--out", lab / "render.csv")
    c = read_table(lab / "render.csv")
    cf = np.column_stack([c["fx"], c["fy"], c["fz"]])
    r = inhap.render_force_model(fm, test)
    np.testing.assert_array_equal(r["force"], cf)
    np.testing.assert_array_equal(r["contact"], c["contact"] > 0)
    r2 = inhap.render_force_model(str(lab / "cli_model.json"), str(lab / "test.csv"))
    np.testing.assert_array_equal(r2["force"], cf)
    r3 = inhap.render_force_model(m, test)
    np.testing.assert_allclose(r3["force"], cf, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(r3["contact"], r["contact"])


def test_eval_recordings_equals_the_program(lab, cli_json):
    ce = cli_json("eval", "recordings", "--train", lab / "train.csv", "--test", lab / "test.csv")
    pf = inhap.evaluate_recordings(str(lab / "train.csv"), str(lab / "test.csv"), progress=False)
    pm = inhap.evaluate_recordings(inhap.read_recording(str(lab / "train.csv")),
                                   inhap.read_recording(str(lab / "test.csv")), progress=False)
    assert pm["train"] == pm["test"] == "recording (in memory)"
    assert pm["estimated"] == ["surface", "normals", "proxy", "friction"]
    for d in (pf, pm):
        assert d["verdict"] in d.pop("text")  # the lines the program prints
        assert d.pop("notes")
        n = len(d.pop("t"))
        assert d.pop("measured").shape == d.pop("rendered").shape == (n, 3)
        assert d.pop("scored").sum() == d["samples"]
    for d in (ce, pf, pm):
        assert d.pop("train_seconds") > 0
    assert pf == ce
    for key in ("train", "test"):
        pm[key] = ce[key]
    assert pm == ce


def test_wrong_arguments_are_type_errors(lab):
    with pytest.raises(TypeError, match="recording"):
        inhap.train_force_model(12, progress=False)
    with pytest.raises(TypeError, match="model"):
        inhap.evaluate_force_model(3.0, str(lab / "test.csv"))
    with pytest.raises(TypeError, match="mesh"):
        inhap.render_force_model(str(lab / "cli_model.json"), str(lab / "test.csv"), mesh=1)
