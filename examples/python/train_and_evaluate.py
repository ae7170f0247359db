"""Train a data-driven force model on a virtual-lab recording and evaluate it on a held-out one;
plot measured vs rendered force per axis (N) over time (s).

    PYTHONPATH=build/python MPLBACKEND=Agg /usr/bin/python3 examples/python/train_and_evaluate.py --out out/py

The proxy q is the lab's true tangential anchor here (what `inhap eval forces --proxy truth`
uses); a real recording gets its qx,qy,qz from `inhap sys proxy`. Units: mm, N, s.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import inhap  # noqa: E402


def with_true_proxy(lab, path):
    rec, truth = lab.recording, lab.truth
    inside = truth["contact"] > 0
    for i, axis in enumerate("xyz"):
        rec["q" + axis] = np.where(inside, truth["anchor"][:, i], rec.p[:, i])
    rec["contact"] = inside.astype(np.float64)
    rec.write(path)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/python-train", help="folder for files and the figure")
    ap.add_argument("--seconds", type=float, default=40.0, help="training recording, s")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    train = with_true_proxy(
        inhap.lab_record(scene="planar", seconds=args.seconds, seed=1, progress=False),
        os.path.join(args.out, "train.csv"))
    test = with_true_proxy(
        inhap.lab_record(scene="planar", seconds=args.seconds / 2, seed=2, progress=False),
        os.path.join(args.out, "test.csv"))
    model_path = os.path.join(args.out, "model.json")
    model = inhap.train_force_model(train, out=model_path, preset="world", centers=150)
    print(model.summary().splitlines()[0])
    report = inhap.evaluate_force_model(model_path, test)
    print(report["text"].strip())
    r = inhap.render_force_model(model_path, test)
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 6))
    for i, name in enumerate("xyz"):
        axes[i].plot(r["t"], r["measured"][:, i], lw=0.8, label="measured")
        axes[i].plot(r["t"], r["force"][:, i], lw=0.8, label="rendered")
        axes[i].set_ylabel(f"f{name} (N)")
    axes[0].legend(loc="upper right")
    axes[-1].set_xlabel("t (s)")
    fig.suptitle("Held-out recording: measured vs rendered force (planar lab object)")
    fig.savefig(os.path.join(args.out, "forces.png"), dpi=120)
    print("figure ->", os.path.join(args.out, "forces.png"))


if __name__ == "__main__":
    main()
