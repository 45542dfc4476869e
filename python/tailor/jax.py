"""JAX adapter: the simulation as differentiable JAX functions (docs/python.md).

    import jax, jax.numpy as jnp
    jax.config.update("jax_enable_x64", True)   # the simulation runs in float64
    import tailor, tailor.jax
    J = tailor.load("scenes/two_material_bar_inverse.json").functional()
    u = tailor.jax.state(J, jnp.asarray(J.x0))          # equilibrium displacements
    loss = lambda z: jnp.sum((tailor.jax.state(J, z)[tip] - target) ** 2) + prior(z)
    g = jax.grad(loss)(jnp.asarray(J.x0))               # dL/du chained through the adjoint

state(J, z) is a jax.custom_vjp function whose primal is J.state(z) and whose VJP is J.vjp,
each a jax.pure_callback to the host: they work under jit and grad (vmap loops over the batch,
one solve per element). objective(J, z) is J(z) with J.gradient as its VJP. Reverse mode only:
custom_vjp has no forward-mode rule (jax.jvp and jax.jacfwd refuse it). The solves run in
float64; results come back in z's dtype (float32 unless jax_enable_x64 is set).
"""
from __future__ import annotations

import inspect
import weakref

import jax
import numpy as np

__all__ = ["state", "objective"]

# pure_callback's batching rule: newer JAX asks for vmap_method (and refuses vmap without it);
# older releases loop over the batch by default and do not know the argument.
_CALLBACK_OPTIONS = ({"vmap_method": "sequential"}
                     if "vmap_method" in inspect.signature(jax.pure_callback).parameters else {})


def _host(function, result, *args):
    return jax.pure_callback(function, result, *args, **_CALLBACK_OPTIONS)


def _design(z):
    return np.asarray(z, dtype=np.float64)


def _check(z):
    if np.ndim(z) != 1:
        raise ValueError(f"z must be a vector, got shape {np.shape(z)}")


class _Adapter:
    """The custom_vjp functions of one functional (made once, so that jit caches them)."""

    def __init__(self, functional):
        self.state = self._make_state(functional)
        self.objective = self._make_objective(functional)

    @staticmethod
    def _make_state(functional):
        shape = tuple(functional.rest_positions.shape)

        def host_state(z):
            return np.asarray(functional.state(_design(z)), dtype=np.asarray(z).dtype)

        def host_vjp(z, cotangent):
            gradient = functional.vjp(_design(z), np.asarray(cotangent, dtype=np.float64))
            return np.asarray(gradient, dtype=np.asarray(z).dtype)

        @jax.custom_vjp
        def state(z):
            return _host(host_state, jax.ShapeDtypeStruct(shape, z.dtype), z)

        def forward(z):
            return state(z), z

        def backward(z, cotangent):
            return (_host(host_vjp, jax.ShapeDtypeStruct(z.shape, z.dtype), z, cotangent),)

        state.defvjp(forward, backward)
        return state

    @staticmethod
    def _make_objective(functional):
        def host_value_and_gradient(z):
            value, gradient = functional.value_and_gradient(_design(z))
            dtype = np.asarray(z).dtype
            return np.asarray(value, dtype=dtype), np.asarray(gradient, dtype=dtype)

        def value_and_gradient(z):
            result = (jax.ShapeDtypeStruct((), z.dtype), jax.ShapeDtypeStruct(z.shape, z.dtype))
            return _host(host_value_and_gradient, result, z)

        @jax.custom_vjp
        def objective(z):
            return value_and_gradient(z)[0]

        def forward(z):
            value, gradient = value_and_gradient(z)
            return value, gradient

        def backward(gradient, cotangent):
            return (cotangent * gradient,)

        objective.defvjp(forward, backward)
        return objective


_adapters: "weakref.WeakKeyDictionary[object, _Adapter]" = weakref.WeakKeyDictionary()


def _adapter(functional):
    adapter = _adapters.get(functional)
    if adapter is None:
        adapter = _adapters[functional] = _Adapter(functional)
    return adapter


def state(functional, z):
    """The equilibrium displacements at design z (num_vertices x dim) as a JAX array whose VJP
    is functional.vjp: one adjoint solve per backward pass."""
    _check(z)
    return _adapter(functional).state(z)


def objective(functional, z):
    """The scene's objective J(z) as a JAX scalar whose VJP is the adjoint gradient."""
    _check(z)
    return _adapter(functional).objective(z)
