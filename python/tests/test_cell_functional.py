# The reduced functional of a periodic cell's density design from Python (tailor.CellFunctional):
# J and its Taylor test as `tailor run` minimizes it; the periodic fluctuations per unit macro
# strain as arrays; J.jvp against central differences of J.state (through the density filter
# and the Heaviside projection) and J.vjp as its exact transpose; a loss of the fluctuations
# written in Python passes its Taylor test with J.vjp as gradient; and the physics against
# closed forms: a homogeneous cell's effective tensor is its material's, and a two-phase
# laminate has the layered-medium tensor (Backus 1962, J. Geophys. Res. 67, 4427; Milton, The
# Theory of Composites, chapter 9): harmonic (Reuss) means of C_2222 and of the shear modulus
# across the layers, the arithmetic (Voigt) mean less the Poisson coupling along them. The
# shipped auxetic design passes its Taylor test; scipy_minimize keeps the volume constraint.
import numpy as np
import pytest

import tailor
from conftest import assert_taylor_of_state_loss, scene_path

E0, NU, E_MIN = 1.0, 0.3, 0.01


def laminate_design(filter_radius, projection, grid=(4, 20)):
    # A square plane-strain cell on a 4 x 20 grid, phase 1 the layer 0 <= y < 0.4 (element rows
    # end at y = 0.4, so the layer's interfaces are element edges).
    return {
        "type": "periodic_cell", "name": "laminate_design",
        "cell": {"lattice": [[1, 0], [0, 1]], "grid": list(grid), "split": "crossed"},
        "plane": "strain",
        "materials": [{"youngs_modulus": 1, "poisson_ratio": NU}, {"youngs_modulus": 1, "poisson_ratio": NU}],
        "phases": [{"phase": 1, "slab": {"axis": 1, "from": 0.0, "to": 0.4}}],
        "design": {
            "material": {"youngs_modulus": E0, "poisson_ratio": NU, "min_youngs_modulus": E_MIN, "penalty": 3},
            "filter_radius": filter_radius, "max_volume_fraction": 0.5,
            "initial_density": [0.3, 0.8], "perturbation": 0.2, "seed": 3, "projection": projection,
            "objective": {
                "entries": {"values": [{"row": 0, "col": 0, "value": 0.5}, {"row": 2, "col": 2, "value": 0.05}]},
                "poisson_ratio": {"target": 0.1, "pairs": [[[1, 0], [0, 1]]]},
            },
        },
    }


@pytest.fixture(scope="module")
def cell():
    # Filter radius 0.12 (several elements) and projection beta = 2: the chain z -> E is not trivial.
    return tailor.load(laminate_design(0.12, [2, 8])).functional()


@pytest.fixture(scope="module")
def sharp():
    # Filter radius 0.01, below the distance between element centroids: rho = z.
    return tailor.load(laminate_design(0.01, [0])).functional()


def plane_strain_tensor(E, nu):
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    return np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])


def test_functional_of_a_cell_design_scene(cell):
    assert isinstance(cell, tailor.CellFunctional)
    m = cell.elements.shape[0]
    assert cell.size == m and len(cell.design_labels) == m and cell.design_labels[0] == "density[0]"
    lower, upper = cell.bounds
    assert np.all(lower == 0) and np.all(upper == 1)
    assert np.all((cell.x0 >= 0) & (cell.x0 <= 1))
    u = cell.state(cell.x0)
    assert u.shape == (3,) + cell.rest_positions.shape and u.dtype == np.float64
    fraction, gradient = cell.volume_fraction(cell.x0)
    assert 0 < fraction < 1 and gradient.shape == (m,) and cell.max_volume_fraction == 0.5
    assert cell.optimizer["backend"] == "nlopt_mma"


def test_jvp_matches_central_differences_and_vjp_is_its_transpose(cell):
    rng = np.random.default_rng(23)
    z = np.clip(cell.x0 + 0.05 * rng.standard_normal(cell.size), 0.05, 0.95)
    dz = rng.standard_normal(cell.size)
    jvp = cell.jvp(z, dz)
    h = 1e-5
    difference = (cell.state(z + h * dz) - cell.state(z - h * dz)) / (2 * h)
    assert np.linalg.norm(jvp - difference) < 1e-6 * np.linalg.norm(difference)
    # A tangent 1% off fails the same check.
    assert np.linalg.norm(1.01 * jvp - difference) > 1e-3 * np.linalg.norm(difference)
    W = rng.standard_normal(jvp.shape)
    assert cell.vjp(z, W) @ dz == pytest.approx(np.sum(W * jvp), rel=1e-9)


def test_a_python_loss_of_the_fluctuations_passes_its_taylor_test(cell):
    rng = np.random.default_rng(29)
    z = np.clip(cell.x0, 0.05, 0.95)
    target = cell.state(np.clip(z + 0.1 * rng.standard_normal(cell.size), 0, 1))

    def loss(u):
        return 0.5 * np.sum((u - target) ** 2)

    gradient = cell.vjp(z, cell.state(z) - target)
    assert_taylor_of_state_loss(loss, cell.state, z, rng.standard_normal(cell.size), gradient, 0.002)


def test_taylor_test_of_the_design_objective(cell):
    result = cell.taylor_test(z=np.clip(cell.x0, 0.05, 0.95))
    assert result["passed"] and result["rate1"] >= 1.9, result["table"]


def test_the_shipped_auxetic_design():
    # scenes/homogenization/auxetic_2d.json: 6400 elements, plane stress, projection stages.
    J = tailor.load(str(scene_path("homogenization/auxetic_2d.json"))).functional()
    assert J.size == 6400 and J.state(J.x0).shape == (3, J.rest_positions.shape[0], 2)
    result = J.taylor_test()
    assert result["passed"] and result["rate1"] >= 1.9, result["table"]
    rng = np.random.default_rng(37)
    dz = rng.standard_normal(J.size)
    W = rng.standard_normal((3,) + J.rest_positions.shape)
    assert J.vjp(J.x0, W) @ dz == pytest.approx(np.sum(W * J.jvp(J.x0, dz)), rel=1e-9)


def test_a_homogeneous_cell_has_its_materials_tensor(sharp):
    z = np.ones(sharp.size)
    np.testing.assert_allclose(sharp.stiffness(z), plane_strain_tensor(E0, NU), rtol=1e-10, atol=1e-12)
    assert np.abs(sharp.state(z)).max() < 1e-12  # no fluctuation in a homogeneous cell


def test_a_laminate_has_the_layered_media_tensor(sharp):
    centroids = sharp.rest_positions[sharp.elements].mean(axis=1)
    layer = centroids[:, 1] < 0.4
    z = np.where(layer, 1.0, 0.0)
    np.testing.assert_allclose(sharp.youngs_modulus(z), np.where(layer, E0, E_MIN), rtol=1e-14)
    C = sharp.stiffness(z)
    stiff, soft = plane_strain_tensor(E0, NU), plane_strain_tensor(E_MIN, NU)
    f = 0.4

    def mean(a, b):  # the volume average over the two layers
        return f * a + (1 - f) * b

    # The exact effective tensor of a laminate with normal y (Backus 1962; Milton, chapter 9):
    # across the layers the harmonic (Reuss) means, along them the arithmetic (Voigt) mean less
    # the Poisson coupling that the layers' continuity across the interfaces releases.
    across = 1 / mean(1 / stiff[1, 1], 1 / soft[1, 1])
    coupling = across * mean(stiff[0, 1] / stiff[1, 1], soft[0, 1] / soft[1, 1])
    along = mean(stiff[0, 0] - stiff[0, 1] ** 2 / stiff[1, 1], soft[0, 0] - soft[0, 1] ** 2 / soft[1, 1]) \
        + coupling**2 / across
    shear = 1 / mean(1 / stiff[2, 2], 1 / soft[2, 2])
    expected = np.array([[along, coupling, 0], [coupling, across, 0], [0, 0, shear]])
    np.testing.assert_allclose(C, expected, rtol=1e-9, atol=1e-12)
    assert C[1, 1] < C[0, 0] < mean(stiff[0, 0], soft[0, 0])  # between the bounds, stiffer along
    # Stretched along x, the layers stay straight (no x fluctuation) and thicken by different
    # amounts (their lateral stresses balance); sheared, they slide (u~_x varies with y).
    u = sharp.state(z)
    assert np.abs(u[0][:, 0]).max() < 1e-12 and np.abs(u[0][:, 1]).max() > 1e-3
    assert np.abs(u[2][:, 0]).max() > 1e-2


def test_torch_adapter_runs_through_the_cell(sharp):
    torch = pytest.importorskip("torch")
    from tailor.torch import state

    # Three design directions (a random basis B) keep the finite differences few: z = z0 + B w.
    base = torch.tensor(np.clip(sharp.x0, 0.1, 0.9), dtype=torch.float64)
    basis = torch.tensor(np.random.default_rng(31).standard_normal((sharp.size, 3)))
    w = torch.zeros(3, dtype=torch.float64, requires_grad=True)
    assert torch.autograd.gradcheck(lambda w: state(sharp, base + 0.01 * basis @ w)[2, 4:6], (w,), eps=1e-6,
                                    atol=1e-7, rtol=1e-4, check_forward_ad=True)


def test_bad_cotangents_and_scenes_are_value_errors(sharp):
    shape = (3,) + sharp.rest_positions.shape
    with pytest.raises(ValueError, match=r"dL_du has shape \(2, .*\), the state \(3, "):
        sharp.vjp(sharp.x0, np.zeros((2,) + sharp.rest_positions.shape))
    with pytest.raises(ValueError, match="non-finite"):
        sharp.vjp(sharp.x0, np.full(shape, np.nan))
    with pytest.raises(ValueError, match="z has 3 entries"):
        sharp.state(np.zeros(3))
    document = laminate_design(0.01, [0])
    del document["design"]
    with pytest.raises(tailor.SceneError, match=r"functional\(\) needs .* a periodic cell with a \"design\" "
                                                r"section; this is a periodic_cell scene"):
        tailor.load(document).functional()


def test_scipy_minimize_keeps_the_volume_constraint():
    pytest.importorskip("scipy")
    # SLSQP's dense subproblems grow with the cube of the design's size: a 2 x 10 grid (80 elements).
    small = tailor.load(laminate_design(0.01, [0], grid=(2, 10))).functional()
    start = small.value(small.x0)
    result = tailor.scipy_minimize(small, options={"maxiter": 15})
    assert result.fun < start
    assert np.all((result.x >= 0) & (result.x <= 1))
    assert small.volume_fraction(result.x)[0] <= small.max_volume_fraction + 1e-8
    with pytest.raises(ValueError, match="'L-BFGS-B' takes no constraints"):
        tailor.scipy_minimize(small, method="L-BFGS-B")
