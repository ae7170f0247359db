"""The force model from Python gives the program's numbers: the same lab recording bytes, the
same trained model, the same `model eval` report and `model render` forces."""
import json

import numpy as np
import pytest

import inhap
from conftest import read_table


def with_true_proxy(lab, path):
    """The recording with the lab's true proxy as qx,qy,qz (p out of contact) and contact."""
    rec = lab.recording
    truth = lab.truth
    contact = truth["contact"].astype(np.float64)
    inside = contact > 0
    for i, axis in enumerate("xyz"):
        rec["q" + axis] = np.where(inside, truth["anchor"][:, i], rec.p[:, i])
    rec["contact"] = contact
    rec.write(str(path))
    return str(path)


@pytest.fixture(scope="module")
def recordings(tmp_path_factory, cli):
    d = tmp_path_factory.mktemp("model")
    # The Python lab gives the program's bytes for the same seed.
    cli("lab", "record", "--scene", "planar", "--seconds", 25, "--seed", 1, "--out", d / "cli.csv")
    lab = inhap.lab_record(scene="planar", seconds=25, seed=1, out=str(d / "py.csv"),
                           progress=False)
    for suffix in (".csv", ".truth.csv"):
        assert (d / ("cli" + suffix)).read_bytes() == (d / ("py" + suffix)).read_bytes()
    train = with_true_proxy(lab, d / "train.csv")
    test = with_true_proxy(inhap.lab_record(scene="planar", seconds=12, seed=2, progress=False),
                           d / "test.csv")
    return d, train, test


def test_lab_truth_views(recordings):
    lab = inhap.lab_record(scene="planar", seconds=2, seed=1, progress=False)
    truth = lab.truth
    n = len(lab.recording)
    assert n == 2000 and truth["anchor"].shape == (n, 3) and truth["t"].shape == (n,)
    np.testing.assert_array_equal(truth["t"], lab.recording.t)
    assert set(lab.recording.columns) >= {"rfx", "rfy", "rfz"}


def test_train_eval_render_equal_cli(recordings, cli, cli_json):
    d, train, test = recordings
    flags = dict(preset="world", centers=60, seed=3)
    cli("model", "train", "--recording", train, "--out", d / "cli_model.json", "--preset", "world",
        "--centers", 60, "--seed", 3)
    calls = []
    m = inhap.train_force_model(train, out=str(d / "py_model.json"),
                                progress=lambda *a: calls.append(a), **flags)
    assert calls and calls[-1][1] == pytest.approx(1.0)
    assert m.features == "ue_q_v" and m.bins == 2
    assert any("in contact" in n for n in m.notes)
    # The same model file but for the training's wall time; the same coverage file beside it.
    a = json.loads((d / "cli_model.json").read_text())
    b = json.loads((d / "py_model.json").read_text())
    assert a["train"].pop("seconds") >= 0 and b["train"].pop("seconds") >= 0
    assert a == b
    assert (d / "cli_model.coverage.csv").read_bytes() == (d / "py_model.coverage.csv").read_bytes()
    # model eval: the same report
    ce = cli_json("model", "eval", "--model", d / "cli_model.json", "--recording", test)
    pe = inhap.evaluate_force_model(str(d / "py_model.json"), test)
    assert pe.pop("text") and pe.pop("support_note") and pe.pop("baselines_note")
    assert "baselines" in ce  # mean force and k-NN, fitted on the training recording
    ce["model"] = pe["model"]  # the model file's name
    ce["coverage"]["file"] = pe["coverage"]["file"]
    assert pe == ce
    # model render: the same forces
    cli("model", "render", "--model", d / "cli_model.json", "--recording", test, "--out",
        d / "render.csv")
    c = read_table(d / "render.csv")
    r = inhap.render_force_model(str(d / "py_model.json"), test)
    np.testing.assert_array_equal(r["force"], np.column_stack([c["fx"], c["fy"], c["fz"]]))
    np.testing.assert_array_equal(r["measured"], np.column_stack([c["mfx"], c["mfy"], c["mfz"]]))
    # save / load gives the same forces; force() on arrays equals the replay's model
    m2 = inhap.load_force_model(str(d / "py_model.json"))
    p = r["p"][:200].copy()
    q = r["q"][:200].copy()
    v = np.zeros_like(p)
    np.testing.assert_array_equal(m.force(p, v, q), m2.force(p, v, q))
    p[0] = np.nan
    assert m2.force(p, v, q)[0].tolist() == [0.0, 0.0, 0.0]


def test_train_errors(recordings, tmp_path):
    _, train, _ = recordings
    with pytest.raises(TypeError, match="unexpected keyword"):
        inhap.train_force_model(train, binz=3)
    with pytest.raises(inhap.Error):
        inhap.train_force_model(train, preset="nope", progress=False)
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    with pytest.raises(inhap.ParseError, match="bad.json"):
        inhap.load_force_model(str(bad))


def test_progress_callable_can_stop_a_call(recordings):
    _, train, _ = recordings

    class Stop(Exception):
        pass

    def stop(what, fraction, eta):
        raise Stop(what)

    with pytest.raises(Stop):
        inhap.lab_record(scene="planar", seconds=5, seed=1, progress=stop)
    with pytest.raises(Stop):
        inhap.train_force_model(train, preset="world", centers=30, progress=stop)


def test_errors_carry_the_programs_message(recordings, tmp_path):
    """inhap.Error's text is the line the program prints after 'inhap: error: '."""
    import subprocess

    from conftest import cli_path

    _, _, test = recordings
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "inhap-force-model", "version": 99}')
    r = subprocess.run([cli_path(), "model", "eval", "--model", str(bad), "--recording", test],
                       capture_output=True, text=True)
    assert r.returncode == 1
    line = [x for x in r.stderr.splitlines() if x.startswith("inhap: error: ")][0]
    with pytest.raises(inhap.Error) as e:
        inhap.evaluate_force_model(str(bad), test)
    assert str(e.value) == line[len("inhap: error: "):]


def test_fallback_normal_line_keywords(tmp_path):
    """The fallback's normal line (model train --fallback-normal-near/far) from Python: on by
    default at 2-4 mm, 0 and 0 turn it off, reversed distances are refused naming the flags."""
    lab = inhap.lab_record(scene="planar", seconds=15, seed=1, progress=False)
    path = str(tmp_path / "raw.csv")
    lab.recording.write(path)  # no proxy columns: the proxy is estimated, preset best
    on = inhap.train_force_model(path, centers=30, progress=False)
    assert on.estimated and on.json["fallback"]["normal_near_mm"] == 2.0
    assert on.json["fallback"]["normal_far_mm"] == 4.0
    off = inhap.train_force_model(path, centers=30, fallback_normal_near=0,
                                  fallback_normal_far=0, progress=False)
    assert off.json["fallback"]["normal_far_mm"] == 0.0
    assert off.json["train"]["fallback_normal_far_mm"] == 0.0
    with pytest.raises(inhap.Error, match="--fallback-normal-near"):
        inhap.train_force_model(path, centers=30, fallback_normal_near=5, fallback_normal_far=4,
                                progress=False)
