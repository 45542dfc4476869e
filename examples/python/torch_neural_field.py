#!/usr/bin/env python3
"""Trains a neural field for Young's modulus through the simulator with PyTorch.

The scene is scenes/plate_stripe_inverse.json: a 2D plate with a stiff stripe (3e5) across a
soft plate (1e5), loaded at its free edge. The measurement here is the plate's equilibrium at
the scene's true moduli, u* = u(log E_true), computed by tailor (no noise). A small network maps
each element's centroid to log E, z = z0 + net(centroid), and is trained with Adam on the
relative displacement misfit |u(z) - u*|^2 / |u*|^2. u(z) is tailor.torch.state: its forward pass
is J.state(z), a Newton solve; its backward pass is J.vjp, one adjoint solve. The gradient
therefore flows from the loss through the simulation into the network's weights; the moduli
themselves are not free variables.

    PYTHONPATH=build/python python3 examples/python/torch_neural_field.py [--steps N]

Exits non-zero unless the misfit falls at least 100-fold and the field found is closer to the
truth than the uniform start (volume-weighted relative L2 of E).
"""
import argparse
import pathlib
import sys

import numpy as np
import torch

import tailor
import tailor.torch

ROOT = pathlib.Path(__file__).resolve().parents[2]


def relative_field_error(E, truth, areas):
    return float(np.sqrt(np.sum(areas * (E - truth) ** 2) / np.sum(areas * truth ** 2)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=600, help="Adam steps")
    args = parser.parse_args()

    J = tailor.load(str(ROOT / "scenes" / "plate_stripe_inverse.json")).functional()
    points, elements = J.rest_positions, J.elements
    corners = points[elements]                                    # elements x 3 x 2
    centroids = torch.tensor(corners.mean(axis=1))
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    areas = 0.5 * np.abs(edge1[:, 0] * edge2[:, 1] - edge1[:, 1] * edge2[:, 0])
    target = torch.tensor(J.state(np.log(J.truth)))               # u* at the true moduli

    torch.manual_seed(0)
    net = torch.nn.Sequential(torch.nn.Linear(2, 32), torch.nn.Tanh(), torch.nn.Linear(32, 32), torch.nn.Tanh(),
                              torch.nn.Linear(32, 1)).double()
    torch.nn.init.zeros_(net[-1].weight)                          # start from the scene's uniform z0
    torch.nn.init.zeros_(net[-1].bias)
    scale = (centroids.max(0).values - centroids.min(0).values)
    inputs = (centroids - centroids.min(0).values) / scale * 2 - 1
    z0 = torch.tensor(J.x0)
    optimizer = torch.optim.Adam(net.parameters(), lr=0.01)

    def misfit():
        z = z0 + net(inputs).squeeze(1)
        u = tailor.torch.state(J, z)
        return ((u - target) ** 2).sum() / (target ** 2).sum(), z

    first = None
    for step in range(args.steps + 1):
        optimizer.zero_grad()
        loss, z = misfit()
        if first is None:
            first = loss.item()
        if step % 100 == 0 or step == args.steps:
            print(f"step {step:4d}  misfit {loss.item():.3e}")
        if step == args.steps:
            break
        loss.backward()
        optimizer.step()

    E = np.exp(z.detach().numpy())
    start_error = relative_field_error(np.exp(J.x0), J.truth, areas)
    error = relative_field_error(E, J.truth, areas)
    print(f"misfit {first:.3e} -> {loss.item():.3e} ({first / loss.item():.0f}x lower); "
          f"E against the truth: relative L2 {start_error:.3f} at the start, {error:.3f} now")
    ok = first / loss.item() >= 100 and error < start_error
    print("neural field: " + ("reached" if ok else "NOT reached") + " (misfit 100x lower, E closer to the truth)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
