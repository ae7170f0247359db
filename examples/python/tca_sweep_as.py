"""Sweep TCA-MESH's height restoration slope a_s on a flat stiffness map (1 N/mm, a soft 0.25
N/mm band) and plot how far the HIP dips over the soft band at a constant 1 N stroke; CBA
for comparison. The distortion is the HIP height's RMS deviation from the stroke's start (mm).

    PYTHONPATH=build/python MPLBACKEND=Agg /usr/bin/python3 examples/python/tca_sweep_as.py --out out/py

Units: mm, N, N/mm, s.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import inhap  # noqa: E402


def stiffness_map(n=129, spacing=0.5):
    x = np.arange(n) * spacing
    k = np.where((x > 25) & (x < 40), 0.25, 1.0)
    height = np.zeros((n, n))
    return height, np.ascontiguousarray(np.tile(k, (n, 1)))


def distortion(stroke):
    """RMS of the HIP height (mm) around its value at the start of the stroke, in contact."""
    z = stroke["hip"][stroke["contact"], 2]
    x = stroke["hip"][stroke["contact"], 0]
    steady = x > 12
    return float(np.sqrt(np.mean((z[steady] - z[steady][0]) ** 2)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/python-tca", help="folder for the figure")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    h, k = stiffness_map()
    mesh = inhap.grid_to_mesh(h, 0.5, k)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    cba = inhap.simulate_stroke(inhap.MeshModel(mesh), "cba", (8, 32), (56, 32), force=1.0)
    on = cba["contact"]
    ax.plot(cba["hip"][on, 0], cba["hip"][on, 2], "k", lw=1, label=f"CBA ({distortion(cba):.3f})")
    for a_s in (0.01, 0.02, 0.05, 0.1, 0.2):
        s = inhap.simulate_stroke(inhap.MeshModel(mesh, a_s=a_s), "tca", (8, 32), (56, 32),
                                  force=1.0)
        on = s["contact"]
        d = distortion(s)
        print(f"a_s {a_s:.2f}: HIP height distortion RMS {d:.3f} mm")
        ax.plot(s["hip"][on, 0], s["hip"][on, 2], lw=1, label=f"TCA a_s={a_s} ({d:.3f})")
    print(f"CBA: {distortion(cba):.3f} mm")
    ax.axvspan(25, 40, color="0.9", label="k = 0.25 N/mm")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("HIP height (mm)")
    ax.legend(fontsize=8, title="distortion RMS mm")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "tca_sweep.png"), dpi=120)
    print("figure ->", os.path.join(args.out, "tca_sweep.png"))


if __name__ == "__main__":
    main()
