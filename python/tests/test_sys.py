"""Sliding yield surfaces from Python: the palpation of a lab scene, the fit from its cycles and
the proxy columns of a recording equal `inhap sys palpate | fit | proxy` byte for byte."""
import numpy as np

import inhap


def test_palpate_fit_proxy_equal_cli(tmp_path, cli):
    cli("sys", "palpate", "--scene", "planar", "--quick", "--points", "grid:2x2", "--seed", 2,
        "--out", tmp_path / "cli.json")
    r = inhap.sys_palpate("planar", points="grid:2x2", seed=2, quick=True,
                          out=str(tmp_path / "py.json"), progress=False)
    assert "f_N" in r["summary"] or len(r["summary"]) > 50
    for suffix in (".json", ".cycles.csv", ".shape.ply", ".refs.csv"):
        assert (tmp_path / ("cli" + suffix)).read_bytes() == \
            (tmp_path / ("py" + suffix)).read_bytes(), suffix
    # fit from the cycles
    cli("sys", "fit", tmp_path / "py.cycles.csv", "--mesh", tmp_path / "py.shape.ply", "--out",
        tmp_path / "fit_cli.json")
    inhap.sys_fit(str(tmp_path / "py.cycles.csv"), str(tmp_path / "fit_py.json"),
                  mesh=str(tmp_path / "py.shape.ply"))
    assert (tmp_path / "fit_cli.json").read_bytes() == (tmp_path / "fit_py.json").read_bytes()
    # the proxy of an exploration recording
    rec_path = tmp_path / "rec.csv"
    cli("lab", "record", "--scene", "planar", "--seconds", 10, "--seed", 5, "--out", rec_path)
    cli("sys", "proxy", "--sys", tmp_path / "cli.json", "--mesh", tmp_path / "cli.shape.ply",
        rec_path, "--out", tmp_path / "rec_q_cli.csv")
    rec = inhap.read_recording(str(rec_path))
    counts = inhap.add_proxy_columns(rec, str(tmp_path / "py.json"),
                                     inhap.read_mesh(str(tmp_path / "py.shape.ply")))
    assert counts["contact"] > 1000 and {"qx", "qy", "qz", "contact", "nx"} <= set(rec.columns)
    cli_rec = inhap.read_recording(str(tmp_path / "rec_q_cli.csv"))
    assert cli_rec.columns == rec.columns
    for name in rec.columns:
        assert (cli_rec[name] == rec[name]).all(), name


def test_data_driven_renderer(tmp_path, cli):
    """The data-driven renderer behind the servo interface: step and replay agree tick for tick,
    and a NaN position gives zero force (as the C++ step)."""
    r = inhap.sys_palpate("planar", points="grid:2x2", quick=True, out=str(tmp_path / "s.json"),
                          progress=False)
    lab = inhap.lab_record(scene="planar", seconds=15, seed=3, progress=False)
    rec = lab.recording
    inhap.add_proxy_columns(rec, r["sys"], inhap.read_mesh(r["shape"]))
    rec.write(str(tmp_path / "train.csv"))
    inhap.train_force_model(str(tmp_path / "train.csv"), out=str(tmp_path / "m.json"),
                            preset="world", centers=60, progress=False)
    dd = inhap.Renderer.data_driven(str(tmp_path / "m.json"), r["sys"], r["shape"])
    assert dd.name == "data-driven"
    test = inhap.lab_record(scene="planar", seconds=4, seed=4, progress=False).recording
    t, p = test.t.copy(), np.ascontiguousarray(test.p)
    clean = dd.replay(t, p)
    assert clean["contact"].sum() > 500
    i = int(np.argmax(np.linalg.norm(clean["force"], axis=1)))  # deep in contact
    assert np.linalg.norm(clean["force"][i]) > 0.5
    p[i] = np.nan
    out = dd.replay(t, p)
    assert out["force"][i].tolist() == [0.0, 0.0, 0.0] and not out["contact"][i]
    assert np.all(np.isfinite(out["force"]))
    dd.reset()
    forces = np.array([dd.step(t[i], p[i]).force for i in range(len(t))])
    np.testing.assert_array_equal(forces, out["force"])
