# The result fields are NumPy views of the C++ result (no copy), read-only, and valid for as
# long as any of them lives (reference: the same numbers read before the rest was dropped).
import gc

import numpy as np

import tailor
from conftest import scene_path


def test_fields_are_views_that_keep_their_owner_alive():
    report = tailor.simulate(str(scene_path("cantilever.json")))
    u = report.fields["displacement"]
    E = report.fields["youngs_modulus"]
    assert not u.flags.owndata and u.base is not None  # a view, not a copy
    assert u.flags.f_contiguous  # Eigen's column-major layout, as is
    assert not u.flags.writeable
    expected = u.copy()
    del report, E
    gc.collect()
    np.testing.assert_array_equal(u, expected)


def test_functional_returns_arrays():
    J = tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()
    g = J.gradient(J.x0)
    assert isinstance(g, np.ndarray) and g.shape == (2,) and g.dtype == np.float64
    # Lists are taken as designs too.
    assert J.value(list(J.x0)) == J.value(J.x0)


def test_reports_serialize_to_json_and_have_a_short_repr():
    import json

    report = tailor.simulate(str(scene_path("cantilever.json")))
    document = json.loads(report.to_json())
    np.testing.assert_array_equal(np.array(document["fields"]["displacement"]), report.fields["displacement"])
    assert document["status"] == report["status"]
    assert len(repr(report)) < 2000 and "displacement" in repr(report)
    # The documented dtypes: float64 values, int32 vertex ids.
    assert report.fields["displacement"].dtype == np.float64
    assert report.fields["elements"].dtype == np.int32
