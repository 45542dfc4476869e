# scipy_minimize with the scene's settings (method="scene": the method closest to its back-end,
# its curvature products, tolerances and bounds) against `tailor run` on the shipped inverse
# scenes whose run and SciPy's each take seconds (about 10 to 20 s on idle cores). Reference: the
# objective in report.json of the tailor executable on the same scene. plate_stripe_inverse.json
# (L-BFGS) is in test_functional.py; the slower scenes' figures are in docs/python.md.
import numpy as np
import pytest

import tailor
import tailor.optimize
from conftest import read_json, scene_path


def run_objective(cli, name, tmp_path):
    code, output = cli("run", scene_path(name), tmp_path / "run", "--quiet")
    assert code == 0, output
    return read_json(tmp_path / "run" / "report.json")["objective"]


def inside(z, bounds):
    return bool(np.all(z >= bounds[0]) and np.all(z <= bounds[1]))


def test_cantilever_handle_newton_cg_scene_with_gauss_newton_products(cli, tmp_path):
    # newton_cg on a least-squares objective (handles + smoothness): tailor uses Gauss-Newton
    # products, and so does SciPy's trust-ncg here.
    objective = run_objective(cli, "cantilever_handle.json", tmp_path)
    J = tailor.load(str(scene_path("cantilever_handle.json"))).functional()
    assert J.optimizer["backend"] == "newton_cg" and J.has_gauss_newton_vector
    assert tailor.optimize.scene_method(J) == "trust-ncg"
    assert tailor.optimize.scene_curvature(J) == J.gauss_newton_vector_product
    result = tailor.scipy_minimize(J)
    assert result.success, result.message
    assert result.tailor_converged, result.tailor_message
    assert inside(result.x, J.bounds)
    # At least tailor's objective (to 1e-6 relative). On this flat minimum tailor stops at its
    # gradient tolerance 0.09% above where SciPy does (docs/python.md).
    assert result.fun <= objective["final"] * (1 + 1e-6)
    assert result.fun == pytest.approx(objective["final"], rel=2e-3)


def test_inclusion_recovery_small_reaches_tailor_runs_objective(cli, tmp_path):
    # An L-BFGS scene (20 material modes, surface observations) where both stop on the
    # objective change (objective_tolerance 1e-12): measured 3.8e-7 relative apart.
    objective = run_objective(cli, "inclusion_recovery_small.json", tmp_path)
    J = tailor.load(str(scene_path("inclusion_recovery_small.json"))).functional()
    assert tailor.optimize.scene_method(J) == "L-BFGS-B"
    result = tailor.scipy_minimize(J)
    assert result.fun == pytest.approx(objective["final"], rel=1e-6)


def test_two_material_bar_reaches_the_zero_residual_minimum_as_tailor_run(cli, tmp_path):
    # An L-BFGS scene whose minimum is 0 (noise-free observations): both reach round-off, so
    # the objectives are compared against J(z0), not relative to each other (~1e-18 both).
    objective = run_objective(cli, "two_material_bar_inverse.json", tmp_path)
    J = tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()
    assert tailor.optimize.scene_method(J) == "L-BFGS-B"
    result = tailor.scipy_minimize(J)
    assert result.tailor_converged, result.tailor_message
    assert objective["final"] <= 1e-12 * objective["initial"]
    assert result.fun <= max(objective["final"] * (1 + 1e-6), 1e-12 * objective["initial"])
    np.testing.assert_allclose(J.design_values(result.x), [1e5, 3e5], rtol=1e-5)


def test_bounds_are_held_by_active_set_rounds_for_newton_methods_without_bounds():
    # The bar as a newton_cg scene with max E = 2e5: the unconstrained minimum (E = 1e5, 3e5) is
    # outside, so trust-ncg's first round leaves the box; the second, with E2 fixed on its bound,
    # reaches what L-BFGS-B (which has bounds) reaches.
    document = read_json(scene_path("two_material_bar_inverse.json"))
    document["inverse"]["design"].update({"max": 2e5, "initial": 1.5e5})
    document["inverse"]["optimizer"] = {"backend": "newton_cg", "max_iterations": 100,
                                        "gradient_tolerance": 1e-10}
    J = tailor.load(document, directory=str(scene_path(".")), name="bar_capped").functional()
    assert tailor.optimize.scene_method(J) == "trust-ncg"
    result = tailor.scipy_minimize(J)
    assert "active-set rounds" in result.message and "1 variables on a bound" in result.message
    assert inside(result.x, J.bounds)
    bounded = tailor.scipy_minimize(J, method="L-BFGS-B", options={"ftol": 1e-15, "gtol": 1e-12})
    assert J.design_values(bounded.x)[1] == pytest.approx(2e5, rel=1e-12)  # at the cap
    assert result.fun == pytest.approx(bounded.fun, rel=1e-6)
    assert result.tailor_converged, result.tailor_message
    # Newton-CG named explicitly is held to the scene's bounds the same way; bounds=None frees it.
    # (Not trust-krylov: SciPy's trlib returned a NaN direction on this 2-variable problem for some
    # last bits of the products, e.g. with OpenBLAS's AVX-512 kernels and another heap layout.)
    newton = tailor.scipy_minimize(J, method="Newton-CG", hessp="gauss_newton")
    assert inside(newton.x, J.bounds) and newton.fun == pytest.approx(bounded.fun, rel=1e-6)
    free = tailor.scipy_minimize(J, method="Newton-CG", bounds=None)
    assert not inside(free.x, J.bounds) and free.fun < bounded.fun


def test_active_set_rounds_end_in_a_corner_when_every_bound_is_active():
    # Both moduli capped at 5e4, below the minimum (1e5, 3e5): the result is the corner.
    document = read_json(scene_path("two_material_bar_inverse.json"))
    document["inverse"]["design"].update({"max": 5e4, "initial": 4e4})
    J = tailor.load(document, directory=str(scene_path(".")), name="bar_corner").functional()
    result = tailor.scipy_minimize(J, method="trust-ncg")
    np.testing.assert_array_equal(result.x, J.bounds[1])
    assert result.success and "every variable on a bound" in result.message, result.message
    assert result.tailor_converged, result.tailor_message


def test_active_set_rounds_share_the_iteration_limit():
    document = read_json(scene_path("two_material_bar_inverse.json"))
    document["inverse"]["design"].update({"max": 2e5, "initial": 1.5e5})
    J = tailor.load(document, directory=str(scene_path(".")), name="bar_capped").functional()
    for limit in (1, 3):
        result = tailor.scipy_minimize(J, method="trust-ncg", options={"maxiter": limit})
        assert result.nit <= limit and len(result.history) <= limit and not result.success
