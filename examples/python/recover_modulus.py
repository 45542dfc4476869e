#!/usr/bin/env python3
"""Recovers a per-element Young's modulus field with SciPy's L-BFGS-B through tailor's Python module.

The scene is scenes/plate_stripe_inverse.json: a 2D plate with a stiff stripe (3e5) across a
soft plate (1e5), observed through noisy full-field displacements; the design is log E per
element, with a smoothness term. The script checks the gradient first (Taylor test), minimizes
with tailor.scipy_minimize, prints the error against the true field, and, when matplotlib is
installed, plots the field it found next to the truth (recovered_modulus.png).

    PYTHONPATH=build/python python3 examples/python/recover_modulus.py [scene.json] [--out DIR]

Exits non-zero unless the Taylor test passes and the field ends within 15% of the truth
(volume-weighted relative L2; the scene's description states about 7% with tailor run).
"""
import argparse
import os
import pathlib
import sys

import numpy as np

import tailor

ROOT = pathlib.Path(__file__).resolve().parents[2]


def element_areas(points, elements):
    a, b, c = (points[elements[:, i]] for i in range(3))
    return 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=str(ROOT / "scenes" / "plate_stripe_inverse.json"))
    parser.add_argument("--out", default="out/recover_modulus", help="where the plot goes")
    args = parser.parse_args()

    J = tailor.load(args.scene).functional()
    check = J.taylor_test()
    print(f"Taylor test: {check['status']}, second-order rate {check['rate1']:.2f}")
    if not check["passed"]:
        print(check["table"])
        return 1

    result = tailor.scipy_minimize(J, options={"maxiter": 500, "gtol": 1e-10})
    E = J.youngs_modulus(result.x)
    print(f"L-BFGS-B: {result.message} after {result.nit} iterations, J = {result.fun:.4e}")
    counters = J.counters
    print(f"{counters['forward_solves']} forward and {counters['adjoint_solves']} adjoint solves")

    points, elements = J.rest_positions, J.elements
    truth = J.truth
    weights = element_areas(points, elements) if points.shape[1] == 2 else np.ones(len(E))
    error = np.sqrt(np.sum(weights * (E - truth) ** 2) / np.sum(weights * truth**2))
    print(f"E from {E.min():.4g} to {E.max():.4g}; relative L2 error against the truth {error:.3f}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot")
    else:
        if points.shape[1] == 2:
            os.makedirs(args.out, exist_ok=True)
            fig, axes = plt.subplots(1, 2, figsize=(10, 3), constrained_layout=True)
            for ax, field, title in zip(axes, (E, truth), ("recovered E", "true E")):
                shown = ax.tripcolor(points[:, 0], points[:, 1], elements, facecolors=field,
                                     vmin=truth.min(), vmax=truth.max())
                ax.set_title(title)
                ax.set_aspect("equal")
            fig.colorbar(shown, ax=axes, label="Young's modulus")
            path = os.path.join(args.out, "recovered_modulus.png")
            fig.savefig(path, dpi=120)
            print(f"wrote {path}")
    return 0 if error < 0.15 else 1


if __name__ == "__main__":
    sys.exit(main())
