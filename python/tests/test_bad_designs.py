# A design that is not a number, is infinite, or overflows its map (z = log E above 709 makes
# E = inf) raises tailor.EvaluationError from every entry point of the reduced functional --
# never a process abort (an exception escaping the parallel element loop used to terminate the
# interpreter). A design whose E underflows to 0 is refused the same way, and the functional
# still evaluates good designs afterwards.
import numpy as np
import pytest

import tailor
from conftest import scene_path

BAD = [np.nan, np.inf, -np.inf, 710.0, -800.0]


@pytest.fixture(scope="module")
def bar():
    return tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()


@pytest.mark.parametrize("bad", BAD)
def test_every_entry_point_raises_evaluation_error(bar, bad):
    z = np.array(bar.x0, dtype=float)
    z[0] = bad
    v = np.ones_like(z)
    calls = {
        "value": lambda: bar.value(z),
        "gradient": lambda: bar.gradient(z),
        "value_and_gradient": lambda: bar.value_and_gradient(z),
        "hessian_vector_product": lambda: bar.hessian_vector_product(z, v),
        "taylor_test": lambda: bar.taylor_test(z=z),
    }
    for name, call in calls.items():
        with pytest.raises(tailor.EvaluationError):
            call()
            pytest.fail(f"{name} accepted z[0] = {bad}")
    # The functional is still usable.
    assert np.isfinite(bar.value(bar.x0))
