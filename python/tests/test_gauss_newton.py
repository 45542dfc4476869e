# The Gauss-Newton products newton_cg uses, through the bindings: J = |r|^2 / 2 with the
# residuals it exposes, w . GN v against central differences of r along w and v (the product is
# (dr/dz)^T (dr/dz) v), GN = H at a zero-residual minimum, and its errors.
import numpy as np
import pytest

import tailor
from conftest import scene_path


@pytest.fixture(scope="module")
def bar():
    return tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()


def test_objective_is_half_the_squared_residuals(bar):
    z = bar.x0 + np.array([0.2, 0.1])
    r = bar.residuals(z)
    assert r.dtype == np.float64 and r.ndim == 1 and r.size > 2
    assert bar.value(z) == pytest.approx(0.5 * r @ r, rel=1e-13)


def test_gauss_newton_products_match_differences_of_the_residuals(bar):
    assert bar.has_gauss_newton_vector
    z = bar.x0 + np.array([0.3, -0.2])
    h = 1e-4  # truncation ~1e-9 relative here; below 3e-5 the equilibrium's round-off shows

    def jr(d):  # (dr/dz) d by central differences
        return (bar.residuals(z + h * d) - bar.residuals(z - h * d)) / (2 * h)

    v, w = np.array([1.0, -0.5]), np.array([0.3, 0.8])
    product = bar.gauss_newton_vector_product(z, v)
    assert w @ product == pytest.approx(jr(w) @ jr(v), rel=1e-7)
    e = np.eye(2)
    np.testing.assert_allclose(product, [jr(e[0]) @ jr(v), jr(e[1]) @ jr(v)], rtol=1e-7)
    # Symmetric and positive: v . GN v = |(dr/dz) v|^2.
    assert v @ product == pytest.approx(jr(v) @ jr(v), rel=1e-7) and v @ product > 0
    # A product 1% off would be seen.
    assert abs(w @ (1.01 * product) - jr(w) @ jr(v)) > 1e-3 * abs(jr(w) @ jr(v))


def test_gauss_newton_is_the_hessian_at_a_zero_residual_minimum(bar):
    truth = np.log(sorted(set(bar.truth)))  # the observations were made with these moduli
    assert bar.value(truth) < 1e-15 * bar.value(bar.x0)
    v = np.array([0.6, -0.8])
    np.testing.assert_allclose(bar.gauss_newton_vector_product(truth, v), bar.hessian_vector_product(truth, v),
                               rtol=1e-6)
    # Away from it they differ (the residual's second derivatives).
    z = bar.x0
    assert not np.allclose(bar.gauss_newton_vector_product(z, v), bar.hessian_vector_product(z, v), rtol=1e-3)


def test_gauss_newton_errors(bar):
    with pytest.raises(ValueError, match="v has 3 entries, the design has 2"):
        bar.gauss_newton_vector_product(bar.x0, np.zeros(3))
    with pytest.raises(ValueError, match="non-finite"):
        bar.gauss_newton_vector_product(bar.x0, np.array([np.nan, 0.0]))
