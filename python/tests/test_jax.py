# The JAX adapter (tailor.jax) with JAX's own gradient checker, jax.test_util.check_grads in
# reverse mode (custom_vjp has no forward rule) and double precision, and its VJP against J.vjp
# and J.gradient. Skipped where JAX is not installed: it is not packaged for Debian 12.
import numpy as np
import pytest

import tailor
from conftest import scene_path

jax = pytest.importorskip("jax", reason="JAX is not installed (not packaged for Debian 12; tailor.jax needs it)")
jax.config.update("jax_enable_x64", True)
import jax.numpy as jnp  # noqa: E402
from jax.test_util import check_grads  # noqa: E402

import tailor.jax  # noqa: E402


@pytest.fixture(scope="module")
def bar():
    return tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()


def tip_vertices(bar):
    x = bar.rest_positions[:, 0]
    return np.flatnonzero(x > x.max() - 1e-12)[:3]


def test_state_passes_check_grads(bar):
    tip = tip_vertices(bar)
    z = jnp.asarray(bar.x0 + np.array([0.1, -0.2]))
    np.testing.assert_allclose(np.asarray(tailor.jax.state(bar, z)), bar.state(np.asarray(z)), rtol=1e-15)
    check_grads(lambda z: tailor.jax.state(bar, z)[tip], (z,), order=1, modes=("rev",), eps=1e-6, atol=1e-6,
                rtol=1e-5)


def test_objective_passes_check_grads(bar):
    z = jnp.asarray(bar.x0 + np.array([0.1, -0.2]))
    assert float(tailor.jax.objective(bar, z)) == pytest.approx(bar.value(np.asarray(z)), rel=1e-15)
    check_grads(lambda z: tailor.jax.objective(bar, z), (z,), order=1, modes=("rev",), eps=1e-6, atol=1e-8,
                rtol=1e-5)


def test_grad_of_a_loss_is_one_adjoint_solve_and_works_under_jit(bar):
    tip = tip_vertices(bar)
    z = bar.x0 + np.array([0.1, -0.2])

    def loss(z):
        return jnp.sum(tailor.jax.state(bar, z)[tip] ** 2)

    gradient = jax.jit(jax.grad(loss))(jnp.asarray(z))
    expected = np.zeros(bar.rest_positions.shape)
    expected[tip] = 2 * bar.state(z)[tip]
    np.testing.assert_allclose(np.asarray(gradient), bar.vjp(z, expected), rtol=1e-12)
    np.testing.assert_allclose(np.asarray(jax.grad(lambda z: tailor.jax.objective(bar, z))(jnp.asarray(z))),
                               bar.gradient(z), rtol=1e-12)
