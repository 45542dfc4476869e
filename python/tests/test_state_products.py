# The state and its products through the bindings: J.jvp against central differences of
# J.state, J.vjp as the exact transpose of J.jvp, a Taylor test of a loss L(u(z)) written in
# Python with J.vjp as its gradient (first-order remainder at rate 1, second-order at >= 1.9),
# and the PyTorch adapter against torch.autograd.gradcheck in double precision.
import numpy as np
import pytest

import tailor
from conftest import scene_path


@pytest.fixture(scope="module")
def bar():
    return tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()


def loss(u, target):
    return 0.5 * np.sum((u - target) ** 2)


def test_state_is_the_equilibrium_displacement(bar):
    u = bar.state(bar.x0)
    assert u.shape == bar.rest_positions.shape and u.dtype == np.float64
    assert np.abs(u).max() > 0
    # The clamped end (x = 0) does not move.
    clamped = bar.rest_positions[:, 0] < 1e-12
    assert clamped.any() and np.abs(u[clamped]).max() == 0


def test_jvp_matches_central_differences_and_vjp_is_its_transpose(bar):
    z = bar.x0 + np.array([0.2, -0.1])
    dz = np.array([1.0, -0.5])
    jvp = bar.jvp(z, dz)
    h = 1e-5
    difference = (bar.state(z + h * dz) - bar.state(z - h * dz)) / (2 * h)
    assert np.linalg.norm(difference - jvp) < 1e-6 * np.linalg.norm(jvp)
    w = np.random.default_rng(3).standard_normal(jvp.shape)
    assert bar.vjp(z, w) @ dz == pytest.approx(np.sum(w * jvp), rel=1e-9)


def test_a_python_loss_of_the_state_passes_its_taylor_test(bar):
    z = bar.x0
    target = bar.state(z + np.array([-0.3, 0.4]))  # the state of another design
    value = loss(bar.state(z), target)
    gradient = bar.vjp(z, bar.state(z) - target)
    dz = np.array([0.7, -1.0])
    steps = [0.1 / 2**k for k in range(5)]
    r0 = [abs(loss(bar.state(z + h * dz), target) - value) for h in steps]
    r1 = [abs(loss(bar.state(z + h * dz), target) - value - h * gradient @ dz) for h in steps]
    rate0 = [np.log2(a / b) for a, b in zip(r0, r0[1:])]
    rate1 = [np.log2(a / b) for a, b in zip(r1, r1[1:])]
    assert min(rate0) > 0.8 and max(rate0) < 1.2, rate0  # the first-order regime: rate 1
    assert min(rate1) >= 1.9, rate1
    # A gradient 1% off is seen: its remainder falls at rate 1 at the smallest steps.
    r_bad = [abs(loss(bar.state(z + h * dz), target) - value - 1.01 * h * gradient @ dz) for h in steps]
    assert np.log2(r_bad[-2] / r_bad[-1]) < 1.5


def test_bad_cotangents_and_directions_are_value_errors(bar):
    with pytest.raises(ValueError, match="shape"):
        bar.vjp(bar.x0, np.zeros((3, 3)))
    bad = np.zeros(bar.rest_positions.shape)
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        bar.vjp(bar.x0, bad)
    with pytest.raises(ValueError, match="non-finite"):
        bar.jvp(bar.x0, np.array([np.inf, 0.0]))
    with pytest.raises(tailor.EvaluationError):
        bar.state(np.array([np.nan, 0.0]))


def test_torch_adapter_passes_gradcheck(bar):
    torch = pytest.importorskip("torch", reason="PyTorch is not installed (Debian: python3-torch)")
    import tailor.torch

    tip = np.flatnonzero(bar.rest_positions[:, 0] > bar.rest_positions[:, 0].max() - 1e-12)[:3]
    z = torch.tensor(bar.x0 + np.array([0.1, -0.2]), dtype=torch.float64, requires_grad=True)
    assert torch.autograd.gradcheck(lambda z: tailor.torch.state(bar, z)[tip], (z,), eps=1e-6, atol=1e-6,
                                    rtol=1e-5)
    assert torch.autograd.gradcheck(lambda z: tailor.torch.objective(bar, z), (z,), eps=1e-6, atol=1e-8,
                                    rtol=1e-5)
    # backward is one adjoint solve with the loss's dL/du, the same as J.vjp.
    u = tailor.torch.state(bar, z)
    (u[tip] ** 2).sum().backward()
    expected = np.zeros(bar.rest_positions.shape)
    expected[tip] = 2 * bar.state(z.detach().numpy())[tip]
    np.testing.assert_allclose(z.grad.numpy(), bar.vjp(z.detach().numpy(), expected), rtol=1e-12)


def test_quadratic_elements_give_the_vertices_state_and_its_products():
    # "mesh": {"order": 2}: the state holds the edge nodes too; J.state and the products are the
    # vertices' (the head of the state), with dL/du zero on the edge nodes.
    import json
    with open(scene_path("two_material_bar_inverse.json")) as f:
        doc = json.load(f)
    doc["mesh"]["order"] = 2
    J = tailor.load(doc, directory=str(scene_path("two_material_bar_inverse.json").parent)).functional()
    z = J.x0 + np.array([0.2, -0.1])
    dz = np.array([1.0, -0.5])
    u = J.state(z)
    assert u.shape == J.rest_positions.shape and np.abs(u).max() > 0
    jvp = J.jvp(z, dz)
    h = 1e-5
    difference = (J.state(z + h * dz) - J.state(z - h * dz)) / (2 * h)
    assert np.linalg.norm(difference - jvp) < 1e-6 * np.linalg.norm(jvp)
    w = np.random.default_rng(4).standard_normal(jvp.shape)
    assert J.vjp(z, w) @ dz == pytest.approx(np.sum(w * jvp), rel=1e-9)
