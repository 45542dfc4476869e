"""PyTorch adapter: the simulation as differentiable torch operations (docs/python.md).

    import torch
    import tailor, tailor.torch
    J = tailor.load("scenes/two_material_bar_inverse.json").functional()
    z = torch.tensor(J.x0, requires_grad=True)
    u = tailor.torch.state(J, z)        # equilibrium displacements, num_vertices x dim
    loss = ((u[tip] - target) ** 2).sum() + prior(z)
    loss.backward()                      # z.grad: dL/du chained through the adjoint

state() is an autograd.Function whose forward is J.state(z) and whose backward is J.vjp: one
adjoint solve at the equilibrium per backward pass, whatever the loss; its forward-mode rule
(torch.autograd.forward_ad, torch.func.jvp) is J.jvp, one tangent solve. objective() is J(z)
itself, with J.gradient as its backward. Both run in float64 on the CPU (the simulation's
precision); results come back in z's dtype and device.
"""
from __future__ import annotations

import numpy as np
import torch

__all__ = ["StateFunction", "ObjectiveFunction", "state", "objective"]


def _design(z):
    if z.dim() != 1:
        raise ValueError(f"z must be a vector, got shape {tuple(z.shape)}")
    return z.detach().cpu().numpy().astype(np.float64)


class StateFunction(torch.autograd.Function):
    """u(z): forward J.state(z), backward J.vjp(z, grad_u), forward-mode J.jvp(z, dz)."""

    @staticmethod
    def forward(ctx, z, functional):
        design = _design(z)
        ctx.functional, ctx.design, ctx.like = functional, design, z
        return torch.from_numpy(functional.state(design)).to(dtype=z.dtype, device=z.device)

    @staticmethod
    def backward(ctx, grad_u):
        gradient = ctx.functional.vjp(ctx.design, grad_u.detach().cpu().numpy().astype(np.float64))
        return torch.from_numpy(gradient).to(dtype=ctx.like.dtype, device=ctx.like.device), None

    @staticmethod
    def jvp(ctx, dz, _):
        tangent = ctx.functional.jvp(ctx.design, dz.detach().cpu().numpy().astype(np.float64))
        return torch.from_numpy(tangent).to(dtype=ctx.like.dtype, device=ctx.like.device)


class ObjectiveFunction(torch.autograd.Function):
    """J(z): forward J.value_and_gradient(z), backward grad_J * dJ/dz."""

    @staticmethod
    def forward(ctx, z, functional):
        value, gradient = functional.value_and_gradient(_design(z))
        ctx.save_for_backward(torch.from_numpy(gradient).to(dtype=z.dtype, device=z.device))
        return torch.tensor(value, dtype=z.dtype, device=z.device)

    @staticmethod
    def backward(ctx, grad_value):
        (gradient,) = ctx.saved_tensors
        return grad_value * gradient, None


def state(functional, z):
    """The equilibrium displacements at design z (num_vertices x dim) as a torch tensor that
    backpropagates to z through the adjoint."""
    return StateFunction.apply(z, functional)


def objective(functional, z):
    """The scene's objective J(z) as a torch scalar that backpropagates to z."""
    return ObjectiveFunction.apply(z, functional)
