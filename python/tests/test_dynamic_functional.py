# The trajectory functional of a dynamic scene from Python (tailor.DynamicFunctional): J and its
# Taylor test as `tailor gradcheck`; the trajectory as an array; J.vjp against central
# differences of J.state along a direction, and, with dL/dU the objective's own, equal to the
# gradient; J.jvp (the forward tangent pass through the steps) against central differences of
# the whole trajectory and as the exact transpose of J.vjp, and its forward-mode use in torch; a loss of the trajectory written in Python passes its Taylor test (first-order
# remainder at rate 1, second-order at >= 1.9) with J.vjp as gradient, and a wrong gradient fails.
import numpy as np
import pytest

import tailor
from conftest import assert_taylor_of_state_loss, scene_path


@pytest.fixture(scope="module")
def beam():
    # scenes/swinging_beam.json (a 4 m beam clamped at x = 0 swinging under gravity, Newmark,
    # Rayleigh damping), shortened to 20 steps with targets at steps 10 and 20.
    path = scene_path("swinging_beam.json")
    doc = tailor.load(str(path)).document
    doc["dynamics"]["steps"] = 20
    doc["dynamics"]["objective"]["steps"] = [10, 20]
    return tailor.load(doc, directory=str(path.parent), name="swinging_beam_short").functional()


def tip(beam):
    return np.flatnonzero(np.abs(beam.rest_positions[:, 0] - 4.0) < 1e-9)


def test_functional_of_a_dynamic_scene(beam):
    assert isinstance(beam, tailor.DynamicFunctional)
    m = beam.elements.shape[0]
    assert beam.size == 2 * m + 2  # log E, log density per element; alpha, beta
    assert beam.design_labels[0] == "log_youngs_modulus[0]" and beam.design_labels[-1] == "rayleigh_beta"
    assert beam.bounds is None


def test_state_is_the_trajectory(beam):
    U = beam.state(beam.x0)
    assert U.shape == (21,) + beam.rest_positions.shape and U.dtype == np.float64
    assert np.abs(U[0]).max() == 0  # starts at rest
    assert U[-1][tip(beam)][:, 2].mean() < 0  # the tip falls under gravity
    clamped = beam.rest_positions[:, 0] < 1e-12
    assert np.abs(U[:, clamped]).max() == 0


def test_vjp_matches_central_differences_of_the_state(beam):
    rng = np.random.default_rng(11)
    z = beam.x0 + 0.02 * rng.standard_normal(beam.size)
    dz = rng.standard_normal(beam.size)
    W = rng.standard_normal(beam.state(z).shape)
    h = 1e-5
    difference = np.sum(W * (beam.state(z + h * dz) - beam.state(z - h * dz))) / (2 * h)
    assert beam.vjp(z, W) @ dz == pytest.approx(difference, rel=1e-6)


def test_vjp_of_the_objectives_own_cotangent_is_the_gradient(beam):
    # J = 1/2 sum over steps 10 and 20 of |x_tip - (X_tip + (0, 0, -0.2))|^2.
    z = beam.x0
    U = beam.state(z)
    dL_dU = np.zeros_like(U)
    for step in (10, 20):
        dL_dU[step, tip(beam)] = U[step, tip(beam)] - np.array([0.0, 0.0, -0.2])
    np.testing.assert_allclose(beam.vjp(z, dL_dU), beam.gradient(z), rtol=1e-9, atol=1e-14 * np.abs(beam.gradient(z)).max())
    assert beam.value(z) == pytest.approx(0.5 * np.sum(dL_dU**2), rel=1e-12)


def test_a_python_loss_of_the_trajectory_passes_its_taylor_test(beam):
    rng = np.random.default_rng(13)
    z = beam.x0
    # The tip's mean height over the whole motion.
    t = tip(beam)

    def loss(U):
        return np.mean(U[:, t, 2]) ** 2

    U = beam.state(z)
    dL_dU = np.zeros_like(U)
    dL_dU[:, t, 2] = 2 * np.mean(U[:, t, 2]) / (U.shape[0] * t.size)
    dz = rng.standard_normal(beam.size)
    dz[-2:] *= [0.2, 1e-3]  # alpha and beta on their own scales (beta = 1e-3 must stay positive)
    assert_taylor_of_state_loss(loss, beam.state, z, dz, beam.vjp(z, dL_dU), 0.05)


def test_jvp_matches_central_differences_and_vjp_is_its_transpose(beam):
    rng = np.random.default_rng(17)
    z = beam.x0 + 0.02 * rng.standard_normal(beam.size)
    dz = rng.standard_normal(beam.size)
    dz[-2:] *= [0.2, 1e-3]  # alpha and beta on their own scales
    jvp = beam.jvp(z, dz)
    assert jvp.shape == (21,) + beam.rest_positions.shape and jvp.dtype == np.float64
    assert np.abs(jvp[0]).max() == 0  # the initial state is not designed
    h = 1e-5
    difference = (beam.state(z + h * dz) - beam.state(z - h * dz)) / (2 * h)
    assert np.linalg.norm(jvp - difference) < 1e-5 * np.linalg.norm(difference)
    # The check sees a tangent without the damping parameters' terms (their part of dz dropped).
    partial = dz.copy()
    partial[-2:] = 0
    assert np.linalg.norm(beam.jvp(z, partial) - difference) > 1e-3 * np.linalg.norm(difference)
    W = rng.standard_normal(jvp.shape)
    assert beam.vjp(z, W) @ dz == pytest.approx(np.sum(W * jvp), rel=1e-9)
    with pytest.raises(ValueError, match="dz has 3 entries"):
        beam.jvp(z, np.zeros(3))


def test_torch_forward_mode_runs_through_the_trajectory(beam):
    torch = pytest.importorskip("torch")
    import torch.autograd.forward_ad as fwAD
    from tailor.torch import state

    rng = np.random.default_rng(19)
    z = beam.x0
    dz = rng.standard_normal(beam.size)
    dz[-2:] *= [0.2, 1e-3]
    with fwAD.dual_level():
        dual = fwAD.make_dual(torch.tensor(z), torch.tensor(dz))
        tangent = fwAD.unpack_dual(state(beam, dual)).tangent
    np.testing.assert_allclose(tangent.numpy(), beam.jvp(z, dz), rtol=0, atol=0)


def test_taylor_test_is_the_scenes_gradcheck(beam):
    result = beam.taylor_test()
    assert result["passed"] and result["rate1"] >= 1.9, result["table"]


def test_bad_cotangents_are_value_errors(beam):
    shape = (21,) + beam.rest_positions.shape
    with pytest.raises(ValueError, match=r"dL_dU has shape \(20, .*\), the trajectory \(21, "):
        beam.vjp(beam.x0, np.zeros((20,) + beam.rest_positions.shape))
    with pytest.raises(ValueError, match="non-finite"):
        beam.vjp(beam.x0, np.full(shape, np.nan))


def test_a_dynamic_scene_without_objective_is_refused():
    doc = tailor.load(str(scene_path("swinging_beam.json"))).document
    del doc["dynamics"]["objective"]
    with pytest.raises(tailor.SceneError, match=r"dynamics\.objective: a dynamic scene's functional\(\) needs"):
        tailor.load(doc, directory=str(scene_path("swinging_beam.json").parent)).functional()
