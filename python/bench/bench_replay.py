"""Benchmark of inhap.Renderer.replay against the same servo loop in C++ (replay_loop.cpp), and
of the per-call overhead of Renderer.step from Python. Not a test: run by hand after a build.

    INHAP_BUILD=build /usr/bin/python3 python/bench/bench_replay.py [--ticks 1000000]

The map: a bumpy 257 x 257 height map at 0.39 mm with a stiffness map (131,072 triangles, the
size of bench_render); the path: a probe pressing 1-3 mm into it while circling at about 50
mm/s, one row per 1 kHz tick. Units: mm, N, s; times in s and microseconds per tick.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

BUILD = os.environ.get("INHAP_BUILD", "build")
sys.path.insert(0, os.path.join(BUILD, "python"))
import inhap  # noqa: E402


def bumpy_map(n=257, spacing=0.39):
    y, x = np.mgrid[0:n, 0:n].astype(np.float64) * spacing
    h = 0.8 * np.sin(x / 3.1) * np.cos(y / 4.3) + 0.5 * np.sin((x + y) / 7.7)
    k = 0.6 + 0.4 * np.cos(x / 9.0) * np.sin(y / 11.0)
    return inhap.grid_to_mesh(np.ascontiguousarray(h), spacing, np.ascontiguousarray(k))


def circling_path(ticks, centre=50.0):
    t = np.arange(ticks, dtype=np.float64) * 1e-3
    a = t * 2 * np.pi / 4.0  # a 30 mm circle in 4 s: ~47 mm/s
    depth = 2.0 + np.sin(t * 2 * np.pi / 1.3)
    p = np.column_stack([centre + 15 * np.cos(a), centre + 15 * np.sin(a), 1.3 - depth])
    return t, np.ascontiguousarray(p)


def best_of(n, fn):
    best = float("inf")
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ticks", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--algorithm", default="tca", choices=["tca", "cba"])
    args = ap.parse_args()
    mesh = bumpy_map()
    t, p = circling_path(args.ticks)
    with tempfile.TemporaryDirectory() as d:
        mesh_path, path_csv = os.path.join(d, "map.ply"), os.path.join(d, "path.csv")
        mesh.write(mesh_path)
        inhap.Recording(t, p, np.zeros_like(p)).write(path_csv)
        exe = os.path.join(BUILD, "python", "inhap_replay_loop")
        out = subprocess.run([exe, mesh_path, path_csv, args.algorithm, str(args.repeats)],
                             capture_output=True, text=True, check=True).stdout.strip()
        print("C++ loop:   ", out)
        cpp_s = float(out.split()[2])
        model = inhap.MeshModel(inhap.read_mesh(mesh_path))
    r = getattr(inhap.Renderer, args.algorithm)(model)
    result = {}

    def run():
        result["out"] = r.replay(t, p)

    py_s = best_of(args.repeats, run)
    fz = np.add.accumulate(result["out"]["force"][:, 2])[-1]  # in order, as the C++ loop sums
    contact = result["out"]["contact"].mean()
    print(f"Python replay: {len(t)} ticks {py_s:.6f} s best of {args.repeats} "
          f"({py_s / len(t) * 1e6:.4f} us/tick), sum fz {fz:.17g}, contact {contact:.3f}")
    print(f"replay / C++ loop = {py_s / cpp_s:.3f} (target <= 1.2)")
    n = min(200_000, len(t))
    rows = [p[i] for i in range(n)]
    times = [float(x) for x in t[:n]]

    def steps():
        r.reset()
        step = r.step
        for i in range(n):
            step(times[i], rows[i])

    step_s = best_of(args.repeats, steps)
    per_call = step_s / n * 1e6
    loop_us = cpp_s / len(t) * 1e6
    print(f"step from Python: {per_call:.3f} us per call ({n} calls), of which the C++ step "
          f"~{loop_us:.3f} us: overhead ~{per_call - loop_us:.3f} us per call")


if __name__ == "__main__":
    main()
