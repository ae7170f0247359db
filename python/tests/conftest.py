"""Fixtures of the inhap pytest suite: the program (INHAP_CLI, set by ctest) and a small
height map with a stiffness map. Units: mm, N, s, N/mm."""
import json
import os
import subprocess

import numpy as np
import pytest

import inhap


def cli_path():
    path = os.environ.get("INHAP_CLI")
    if not path:
        here = os.path.dirname(os.path.abspath(inhap.__file__))
        path = os.path.join(here, "..", "apps", "inhap", "inhap")
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs the program; returns its stdout. Fails the test on a non-zero exit."""
    path = cli_path()
    if not os.path.exists(path):
        pytest.fail(f"the program is not built: {path}")

    def run(*args):
        r = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        assert r.returncode == 0, f"inhap {' '.join(map(str, args))}: {r.stderr}"
        return r.stdout

    return run


@pytest.fixture(scope="session")
def cli_json(cli, tmp_path_factory):
    """Runs the program with --json FILE and returns the parsed file."""

    def run(*args):
        out = tmp_path_factory.mktemp("json") / "out.json"
        cli(*args, "--json", out)
        with open(out) as f:
            return json.load(f)

    return run


def bumpy_map(n=33, spacing=1.0):
    """Height (mm) and stiffness (N/mm) grids, n x n: a bump and a soft blob."""
    y, x = np.mgrid[0:n, 0:n].astype(np.float64) * spacing
    c = (n - 1) * spacing / 2
    r2 = (x - c) ** 2 + (y - c) ** 2
    height = 2.0 * np.exp(-r2 / (2 * (0.2 * n * spacing) ** 2))
    stiffness = 1.0 - 0.7 * np.exp(-((x - 0.3 * n * spacing) ** 2) / 20.0)
    return np.ascontiguousarray(height), np.ascontiguousarray(stiffness)


@pytest.fixture(scope="session")
def map_mesh(tmp_path_factory):
    """A 33 x 33 height map with a stiffness map as a Mesh and as a PLY file."""
    h, k = bumpy_map()
    mesh = inhap.grid_to_mesh(h, 1.0, k)
    path = tmp_path_factory.mktemp("mesh") / "map.ply"
    mesh.write(str(path))
    return mesh, str(path)


def read_table(path):
    """A CSV the program wrote ('#' comment lines, a header row, numbers) as name -> column."""
    with open(path) as f:
        lines = [line for line in f if not line.startswith("#") and line.strip()]
    names = lines[0].strip().split(",")
    data = np.array([[float(x) for x in line.split(",")] for line in lines[1:]]).reshape(
        -1, len(names))
    return {n: np.ascontiguousarray(data[:, i]) for i, n in enumerate(names)}
