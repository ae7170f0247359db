"""Long calls report progress through a Python callable, release the GIL, and stop cleanly on
Ctrl-C (SIGINT) with KeyboardInterrupt."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import inhap


def test_progress_callable_sees_fractions():
    seen = []
    inhap.lab_record(scene="planar", seconds=3, seed=1,
                     progress=lambda what, f, eta: seen.append((what, f, eta)))
    assert seen and all(0.0 <= f <= 1.0 for _, f, _ in seen)
    assert [f for _, f, _ in seen] == sorted(f for _, f, _ in seen)
    with pytest.raises(TypeError, match="progress"):
        inhap.lab_record(scene="planar", seconds=1, progress="yes")
    inhap.lab_record(scene="planar", seconds=1, progress=True)  # tqdm or silent
    inhap.lab_record(scene="planar", seconds=1, progress=None)


def test_ctrl_c_interrupts_a_long_call():
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        inhap.lab_record(scene="planar", seconds=600, seed=1, progress=False)
    timer.join()
    assert time.monotonic() - t0 < 20  # stopped long before the 10-minute recording would end


def test_replay_releases_the_gil(map_mesh):
    r = inhap.Renderer.cba(inhap.MeshModel(map_mesh[0]))
    n = 400_000
    t = np.arange(n, dtype=np.float64) * 1e-3
    p = np.ascontiguousarray(np.column_stack([np.full(n, 16.0), np.full(n, 16.0),
                                              np.sin(t) - 0.5]))
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    th = threading.Thread(target=count)
    th.start()
    time.sleep(0.01)
    before = len(ticks)
    r.replay(t, p)
    during = len(ticks) - before
    stop.set()
    th.join()
    assert during >= 2  # the other thread ran while replay was in C++


def test_ctrl_c_stops_a_training_mid_bin():
    """One bin of 300 centres on 40 s of contact takes many seconds; Ctrl-C one second in stops
    it within a second, before the bin ends (its only progress call would be fraction 1)."""
    import _thread

    lab = inhap.lab_record(scene="planar", seconds=40, seed=4, progress=False)
    rec = lab.recording
    inside = lab.truth["contact"] > 0
    for i, axis in enumerate("xyz"):
        rec["q" + axis] = np.where(inside, lab.truth["anchor"][:, i], rec.p[:, i])
    rec["contact"] = inside.astype(np.float64)
    seen = []
    fired = []

    def interrupt():
        fired.append(time.monotonic())
        _thread.interrupt_main()

    timer = threading.Timer(1.0, interrupt)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        inhap.train_force_model(rec, preset="world", bins=1, centers=300, nonzeros=300,
                                threads=1, progress=lambda w, f, eta: seen.append(f))
    stopped = time.monotonic()
    timer.join()
    assert fired and stopped - fired[0] < 1.0
    assert seen == []  # the bin never finished
