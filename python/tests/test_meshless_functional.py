# The reduced functional of a meshless scene from Python (tailor.MeshlessFunctional): the same J
# and Taylor test as `tailor gradcheck` on the scene (compared with its gradcheck.json), the
# state as the MLS field's values at the nodes, J.jvp against central differences of J.state,
# J.vjp as its transpose, a Python loss of the state by its Taylor test, and the PyTorch adapter
# by torch.autograd.gradcheck.
import copy
import json

import numpy as np
import pytest

import tailor
from conftest import assert_taylor_of_state_loss, read_json
from test_meshless import BAR

# The bar of test_meshless.py with a stiffer tip region: the design is log E outside the region
# and in it (2 variables).
BAR_REGIONS = copy.deepcopy(BAR)
BAR_REGIONS["regions"] = [{"name": "tip", "box": {"lo": [1.5, -1, -1], "hi": [4, 2, 2]}, "youngs_modulus": 2000}]
BAR_REGIONS["inverse"]["per"] = "region"


@pytest.fixture(scope="module")
def bar():
    return tailor.load(BAR, name="bar").functional()


@pytest.fixture(scope="module")
def bar_regions():
    return tailor.load(BAR_REGIONS, name="bar_regions").functional()


def test_functional_of_a_meshless_scene(bar, bar_regions):
    assert isinstance(bar, tailor.MeshlessFunctional)
    assert bar.size == 63 and bar.bounds is None
    assert bar.design_labels[0] == "log_youngs_modulus[0]"
    assert bar.rest_positions.shape == (63, 3)
    assert bar.has_gauss_newton_vector and bar.has_hessian_vector
    assert bar.optimizer["backend"] == "newton_cg"
    assert bar_regions.size == 2
    assert bar_regions.design_labels == ["log_youngs_modulus[outside the regions]", "log_youngs_modulus[tip]"]
    np.testing.assert_array_equal(bar_regions.x0, [0, 0])
    # E = E0 exp(z) per region: the region's E0 is 2000, the others' 1000.
    E = bar_regions.youngs_modulus([np.log(2), np.log(3)])
    tip = bar_regions.rest_positions[:, 0] >= 1.5
    np.testing.assert_allclose(E[tip], 6000, rtol=1e-14)
    np.testing.assert_allclose(E[~tip], 2000, rtol=1e-14)


def test_taylor_test_rates_and_the_clis_gradcheck(bar, cli, tmp_path):
    result = bar.taylor_test()
    assert result["passed"], result["table"]
    assert result["rate0"] == pytest.approx(1.0, abs=0.05) and result["rate1"] >= 1.9, result["table"]
    assert bar.taylor_test(hessian=True)["rate1"] >= 1.9
    # `tailor gradcheck` on the same scene: the same test (seed, steps, remainders).
    path = tmp_path / "bar.json"
    path.write_text(json.dumps(BAR))
    code, output = cli("gradcheck", path, tmp_path / "cli")
    assert code == 0, output
    expected = read_json(tmp_path / "cli" / "gradcheck.json")
    fresh = tailor.load(BAR, name="bar").functional().taylor_test()
    assert fresh["value"] == pytest.approx(expected["value"], rel=1e-12)
    assert fresh["directional_derivative"] == pytest.approx(expected["directional_derivative"], rel=1e-9)
    assert len(fresh["rows"]) == len(expected["rows"])
    for mine, theirs in zip(fresh["rows"], expected["rows"]):
        assert mine["step"] == theirs["step"]
        assert mine["remainder0"] == pytest.approx(theirs["remainder0"], rel=1e-7)
    assert fresh["rate1"] == pytest.approx(expected["rate1"], abs=0.01)


def test_state_is_the_field_at_the_nodes_and_the_clamp_holds_it(bar):
    u = bar.state(bar.x0)
    assert u.shape == (63, 3) and u.dtype == np.float64
    f = bar.fields(bar.x0)
    np.testing.assert_array_equal(f["displacement"], u)
    clamped = bar.rest_positions[:, 0] <= 1e-12
    assert clamped.sum() == 9
    # The transformation method holds the field's values at the clamped nodes at zero, not the
    # coefficients (MLS does not interpolate): these move by a visible fraction of the tip's.
    tip = np.abs(u[:, 2]).max()
    assert np.abs(u[clamped]).max() < 1e-12 * tip
    assert np.abs(f["coefficient_displacement"][clamped]).max() > 1e-3 * tip


def test_jvp_matches_central_differences_and_vjp_is_its_transpose(bar_regions):
    J = bar_regions
    rng = np.random.default_rng(3)
    z = J.x0 + 0.1 * rng.standard_normal(J.size)
    dz = rng.standard_normal(J.size)
    jvp = J.jvp(z, dz)
    h = 1e-5
    difference = (J.state(z + h * dz) - J.state(z - h * dz)) / (2 * h)
    assert np.linalg.norm(difference - jvp) < 1e-6 * np.linalg.norm(jvp)
    w = rng.standard_normal(jvp.shape)
    assert J.vjp(z, w) @ dz == pytest.approx(np.sum(w * jvp), rel=1e-9)
    with pytest.raises(ValueError, match=r"dL_du has shape \(3, 3\), the state \(63, 3\)"):
        J.vjp(z, np.zeros((3, 3)))


def test_a_python_loss_of_the_state_passes_its_taylor_test(bar_regions):
    J = bar_regions
    rng = np.random.default_rng(7)
    z = J.x0
    target = J.state(z + 0.3 * rng.standard_normal(J.size))

    def loss(u):
        return 0.5 * np.sum((u - target) ** 2)

    gradient = J.vjp(z, J.state(z) - target)
    assert_taylor_of_state_loss(loss, J.state, z, rng.standard_normal(J.size), gradient, 0.02)


def test_torch_adapter_passes_gradcheck(bar_regions):
    torch = pytest.importorskip("torch", reason="PyTorch is not installed (Debian: python3-torch)")
    import tailor.torch

    J = bar_regions
    tip = np.flatnonzero(J.rest_positions[:, 0] > J.rest_positions[:, 0].max() - 1e-12)[:3]
    z = torch.tensor(J.x0 + np.array([0.1, -0.2]), dtype=torch.float64, requires_grad=True)
    assert torch.autograd.gradcheck(lambda z: tailor.torch.state(J, z)[tip], (z,), eps=1e-6, atol=1e-8,
                                    rtol=1e-5)
    assert torch.autograd.gradcheck(lambda z: tailor.torch.objective(J, z), (z,), eps=1e-6, atol=1e-10,
                                    rtol=1e-5)
    u = tailor.torch.state(J, z)
    (u[tip] ** 2).sum().backward()
    expected = np.zeros(J.rest_positions.shape)
    expected[tip] = 2 * J.state(z.detach().numpy())[tip]
    np.testing.assert_allclose(z.grad.numpy(), J.vjp(z.detach().numpy(), expected), rtol=1e-12)


def test_functional_needs_an_inverse_section():
    document = copy.deepcopy(BAR)
    document.pop("inverse")
    with pytest.raises(tailor.SceneError, match=r"bar: functional\(\) needs an \"inverse\" section"):
        tailor.load(document, name="bar").functional()


def test_jax_adapter_passes_check_grads(bar_regions):
    # As python/tests/test_jax.py on the FEM bar; skipped where JAX is not installed.
    jax = pytest.importorskip("jax", reason="JAX is not installed (not packaged for Debian 12; tailor.jax needs it)")
    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp
    from jax.test_util import check_grads

    import tailor.jax

    J = bar_regions
    tip = np.flatnonzero(J.rest_positions[:, 0] > J.rest_positions[:, 0].max() - 1e-12)[:3]
    z = jnp.asarray(J.x0 + np.array([0.1, -0.2]))
    np.testing.assert_allclose(np.asarray(tailor.jax.state(J, z)), J.state(np.asarray(z)), rtol=1e-15)
    check_grads(lambda z: tailor.jax.state(J, z)[tip], (z,), order=1, modes=("rev",), eps=1e-6, atol=1e-8,
                rtol=1e-5)
    check_grads(lambda z: tailor.jax.objective(J, z), (z,), order=1, modes=("rev",), eps=1e-6, atol=1e-10,
                rtol=1e-5)


def test_run_returns_the_recovered_design_and_its_fields(tmp_path):
    # The tip region's modulus recovered from the field at three nodes along the bar, as
    # MeshlessScene.GradcheckAndRunRecoverTheTipModulus does from C++: the observations are the
    # state of the bar whose tip region is twice as stiff (E0 2000 in BAR_REGIONS).
    truth = tailor.load(BAR_REGIONS, name="truth").functional()
    u = truth.state(truth.x0)
    X = truth.rest_positions
    document = copy.deepcopy(BAR_REGIONS)
    document["regions"][0]["youngs_modulus"] = 1000
    document["inverse"]["observations"] = []
    for x in (1, 2, 3):
        node = np.flatnonzero(np.all(np.isclose(X, [x, 0.5, 0.5]), axis=1))[0]
        document["inverse"]["observations"].append({"at": [x, 0.5, 0.5], "displacement": u[node].tolist()})
    scene = tailor.load(document, name="bar")
    report = scene.run(out_dir=tmp_path / "run")
    assert report.ok and report.fields["status"] == "converged", report.fields["status"]
    # z = log(E / E0) per region [outside the regions, tip]: the tip's modulus doubles.
    np.testing.assert_allclose(report.fields["design"], [0, np.log(2)], atol=1e-6)
    np.testing.assert_allclose(report.fields["design"], report["z"], rtol=0, atol=0)
    tip = report.fields["rest_positions"][:, 0] >= 1.5
    np.testing.assert_allclose(report.fields["youngs_modulus"][tip], 2000, rtol=1e-5)
    np.testing.assert_allclose(report.fields["displacement"], u, atol=1e-6 * np.abs(u).max())
    # SciPy on the functional from Python reaches the same design.
    result = tailor.scipy_minimize(scene.functional())
    np.testing.assert_allclose(result.x, report.fields["design"], atol=1e-6)
