# The reduced functional of a rod scene from Python (tailor.RodFunctional): the same J and
# Taylor test as `tailor gradcheck` on the scene, the equilibrium as vertex rows, J.jvp against
# central differences of J.state, J.vjp as the exact transpose of J.jvp and, with dL/du the
# objective's own, equal to the gradient; a loss of the state written in Python passes its
# Taylor test (first-order remainder at rate 1, second-order at >= 1.9) with J.vjp as gradient.
import numpy as np
import pytest

import tailor
from conftest import assert_taylor_of_state_loss, scene_path


@pytest.fixture(scope="module")
def beam():
    # A 21-vertex cantilever with per-edge radii designed so that its tip moves 0.02 down under
    # a tip load (scenes/rods/rod_stiffness_design.json), without the scene's regularization:
    # J = 1/2 (u_tip,y - t)^2 / L^2 then depends on z only through the state.
    doc = tailor.load(str(scene_path("rods/rod_stiffness_design.json"))).document
    doc["inverse"].pop("regularization")
    return tailor.load(doc, directory=str(scene_path("rods/rod_stiffness_design.json").parent)).functional()


def test_functional_of_a_rod_scene(beam):
    assert isinstance(beam, tailor.RodFunctional)
    assert beam.size == 20 and beam.bounds is None
    assert beam.design_labels[0].startswith("radius")
    assert beam.rest_positions.shape == (21, 3)
    assert beam.has_gauss_newton_vector


def test_state_is_the_equilibrium_displacement(beam):
    u = beam.state(beam.x0)
    assert u.shape == (21, 3) and u.dtype == np.float64
    # Clamped start; the tip moves down under its load by about Euler-Bernoulli's P L^3 / 3 E I
    # (scene: P = 0.1, E = 1.27e8, radius 0.01, so I = pi 1e-8 / 4): between the spans L = 0.95
    # (the clamped first edge, 0.05 long, taken out) and L = 1.
    assert np.abs(u[0]).max() == 0
    def euler_bernoulli(length):
        return 0.1 * length**3 / (3 * 127323954.47351627 * np.pi * 1e-8 / 4)
    assert euler_bernoulli(0.95) < -u[-1, 1] < euler_bernoulli(1.0)


def test_jvp_matches_central_differences_and_vjp_is_its_transpose(beam):
    rng = np.random.default_rng(5)
    z = beam.x0 + 0.1 * rng.standard_normal(beam.size)
    dz = rng.standard_normal(beam.size)
    jvp = beam.jvp(z, dz)
    h = 1e-5
    difference = (beam.state(z + h * dz) - beam.state(z - h * dz)) / (2 * h)
    assert np.linalg.norm(difference - jvp) < 1e-6 * np.linalg.norm(jvp)
    w = rng.standard_normal(jvp.shape)
    assert beam.vjp(z, w) @ dz == pytest.approx(np.sum(w * jvp), rel=1e-9)


def test_vjp_of_the_objectives_own_cotangent_is_the_gradient(beam):
    z = beam.x0 + 0.05
    u = beam.state(z)
    # J = 1/2 (u_tip,y - t)^2 / (m L^2) with one target (m = 1) on a rod of length L = 1.
    dL_du = np.zeros_like(u)
    dL_du[20, 1] = u[20, 1] - (-0.02)
    np.testing.assert_allclose(beam.vjp(z, dL_du), beam.gradient(z), rtol=1e-10, atol=1e-14)
    assert beam.value(z) == pytest.approx(0.5 * dL_du[20, 1] ** 2, rel=1e-12)


def test_a_python_loss_of_the_state_passes_its_taylor_test(beam):
    rng = np.random.default_rng(7)
    z = beam.x0
    target = beam.state(z + 0.2 * rng.standard_normal(beam.size))

    def loss(u):
        return 0.5 * np.sum((u - target) ** 2)

    gradient = beam.vjp(z, beam.state(z) - target)
    assert_taylor_of_state_loss(loss, beam.state, z, rng.standard_normal(beam.size), gradient, 0.02)


def test_taylor_test_is_the_scenes_gradcheck(beam):
    result = beam.taylor_test()
    assert result["passed"] and result["rate1"] >= 1.9, result["table"]


def test_bad_cotangents_and_designs_are_value_errors(beam):
    with pytest.raises(ValueError, match=r"dL_du has shape \(21, 2\), the state \(21, 3\)"):
        beam.vjp(beam.x0, np.zeros((21, 2)))
    with pytest.raises(ValueError, match="non-finite"):
        beam.vjp(beam.x0, np.full((21, 3), np.nan))
    with pytest.raises(ValueError, match="z has 3 entries, the design has 20"):
        beam.state(np.zeros(3))


def test_torch_adapter_runs_through_the_rod(beam):
    torch = pytest.importorskip("torch")
    from tailor.torch import state

    z = torch.tensor(beam.x0 + 0.05, dtype=torch.float64, requires_grad=True)
    assert torch.autograd.gradcheck(lambda z: state(beam, z)[20], (z,), eps=1e-6, atol=1e-7, rtol=1e-4)
