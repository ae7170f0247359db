"""Tap a virtual-lab object, find the contact points (knee estimate and plain thresholding),
score them against the lab's true contact points (mm) and reconstruct the surface.

    PYTHONPATH=build/python MPLBACKEND=Agg /usr/bin/python3 examples/python/tap_and_reconstruct.py --out out/py

Units: mm, N, s.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import inhap  # noqa: E402


def errors(contacts, truth):
    """Distance (mm) from each detected contact point to its tap's true contact point."""
    tap_at = truth["tap"]
    out = []
    for t_detect, point in zip(contacts.t_detect, contacts.point):
        i = int(np.searchsorted(truth["t"], t_detect))
        i = min(i, len(tap_at) - 1)
        if tap_at[i] >= 0:
            out.append(np.linalg.norm(point - truth["c"][i]))
    return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/python-taps", help="folder for files and the figure")
    ap.add_argument("--seconds", type=float, default=60.0, help="tapping time, s")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    lab = inhap.lab_record(scene="silicone-hemisphere", operator="tap", probe="tip",
                           seconds=args.seconds, seed=1, progress=False)
    est = inhap.contacts_from_recording(lab.recording, method="estimate")
    thr = inhap.contacts_from_recording(lab.recording, method="threshold")
    e_est, e_thr = errors(est, lab.truth), errors(thr, lab.truth)
    print(f"{len(est)} taps; median contact-point error: estimate {np.median(e_est):.3f} mm, "
          f"threshold {np.median(e_thr):.3f} mm")
    mesh, summary = inhap.reconstruct_surface(est.point, est.direction)
    print(summary)
    mesh.write(os.path.join(args.out, "reconstructed.ply"))
    fig = plt.figure(figsize=(10, 4.5))
    ax = fig.add_subplot(1, 2, 1)
    ax.boxplot([e_est, e_thr], labels=["knee estimate", "threshold"])
    ax.set_ylabel("contact-point error (mm)")
    ax3 = fig.add_subplot(1, 2, 2, projection="3d")
    v, f = mesh.vertices, mesh.faces
    ax3.plot_trisurf(v[:, 0], v[:, 1], v[:, 2], triangles=f, cmap="viridis", lw=0)
    ax3.scatter(*est.point.T, s=4, c="k")
    ax3.set_title("reconstruction (mm)")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "taps.png"), dpi=120)
    print("figure ->", os.path.join(args.out, "taps.png"))


if __name__ == "__main__":
    main()
