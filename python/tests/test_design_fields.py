# Fields at any design: scene.simulate with per-element Young's moduli and Poisson's ratios in
# place of the scene's (the same equilibrium as J.state at the matching design, the same as a
# scene that states the values itself), their checks, and J.report(z) with its fields as meshio
# data written without an out_dir.
import json

import numpy as np
import pytest

import tailor
from conftest import scene_path, small_dynamic_scene


@pytest.fixture(scope="module")
def bar():
    scene = tailor.load(str(scene_path("two_material_bar_inverse.json")))
    return scene, scene.functional()


def test_simulate_with_the_moduli_of_a_design_is_the_state_at_that_design(bar, tmp_path):
    scene, J = bar
    z = J.x0 + np.array([0.3, -0.2])
    report = scene.simulate(youngs_modulus=J.youngs_modulus(z), out_dir=tmp_path)
    assert report.ok
    u = J.state(z)
    np.testing.assert_allclose(report.fields["displacement"], u, rtol=0, atol=1e-10 * np.abs(u).max())
    np.testing.assert_array_equal(report.fields["youngs_modulus"], J.youngs_modulus(z))
    # The scene's own moduli give another state: the override is what made them equal.
    plain = scene.simulate()
    assert np.abs(plain.fields["displacement"] - u).max() > 1e-3 * np.abs(u).max()
    # result.vtu holds the moduli it was solved with.
    meshio = pytest.importorskip("meshio", reason="meshio is not installed (Debian: python3-meshio)")
    written = meshio.read(tmp_path / "result.vtu")
    np.testing.assert_array_equal(written.cell_data["youngs_modulus"][0].ravel(), J.youngs_modulus(z))


def test_poisson_ratio_override_equals_a_scene_with_that_ratio(bar):
    scene, J = bar
    document = scene.document
    for material in document["materials"]:
        material["poisson_ratio"] = 0.1
    stated = tailor.load(document, directory=str(scene_path(".")), name="bar_nu_0.1").simulate()
    ne = J.elements.shape[0]
    overridden = scene.simulate(poisson_ratio=np.full(ne, 0.1))
    np.testing.assert_allclose(overridden.fields["displacement"], stated.fields["displacement"], rtol=0,
                               atol=1e-12 * np.abs(stated.fields["displacement"]).max())
    np.testing.assert_array_equal(overridden.fields["poisson_ratio"], np.full(ne, 0.1))
    assert not np.allclose(overridden.fields["displacement"], scene.simulate().fields["displacement"])


@pytest.mark.parametrize("name, value, message", [
    ("youngs_modulus", np.ones(3), r"youngs_modulus has 3 values, the mesh has 192 elements"),
    ("youngs_modulus", np.ones((192, 2)), r"youngs_modulus: expected a vector .* shape \(192, 2\)"),
    ("youngs_modulus", "stiff", r"youngs_modulus: expected one number per element, got str"),
    ("youngs_modulus", np.r_[np.ones(191), -1.0], r"youngs_modulus\[191\] = -1: expected a finite number > 0"),
    ("youngs_modulus", np.r_[np.nan, np.ones(191)], r"youngs_modulus\[0\] = nan: expected a finite number"),
    ("youngs_modulus", np.r_[np.ones(191), np.inf], r"youngs_modulus\[191\] = inf"),
    ("poisson_ratio", np.r_[np.full(191, 0.3), 0.5], r"poisson_ratio\[191\] = 0.5: expected .* > -1 and < 0.5"),
    ("poisson_ratio", np.r_[-1.0, np.full(191, 0.3)], r"poisson_ratio\[0\] = -1: expected .* > -1 and < 0.5"),
])
def test_bad_per_element_values_are_value_errors(bar, name, value, message):
    scene, _ = bar
    with pytest.raises(ValueError, match=message):
        scene.simulate(**{name: value})


def test_overrides_on_a_dynamic_scene_are_refused():
    scene = tailor.load(small_dynamic_scene(), directory=str(scene_path(".")))
    with pytest.raises(ValueError, match="apply to static FEM scenes; this is a dynamic scene"):
        scene.simulate(youngs_modulus=np.ones(8 * 6))


def test_report_at_a_design(bar, tmp_path):
    meshio = pytest.importorskip("meshio", reason="meshio is not installed (Debian: python3-meshio)")
    _, J = bar
    z = J.x0 + np.array([-0.1, 0.4])
    report = J.report(z)
    assert report.ok and report.out_dir is None and report["kind"] == "design"
    assert report["objective"]["value"] == pytest.approx(J.value(z), rel=1e-14)
    terms = report["objective"]["terms"]
    assert [t["type"] for t in terms] == ["synthetic_observations"]
    assert sum(t["value"] for t in terms) == pytest.approx(J.value(z), rel=1e-12)
    assert report["design"]["labels"] == J.design_labels
    np.testing.assert_allclose(report["design"]["values"], J.design_values(z), rtol=1e-15)
    f = report.fields
    np.testing.assert_array_equal(f["displacement"], J.state(z))
    np.testing.assert_array_equal(f["positions"], J.rest_positions + J.state(z))
    np.testing.assert_array_equal(f["youngs_modulus"], J.youngs_modulus(z))
    assert f["poisson_ratio"].shape == (J.elements.shape[0],)
    # meshio: point and cell data by rows, written and read back without an out_dir.
    mesh = report.to_meshio()
    assert set(mesh.point_data) == {"displacement", "positions"}
    assert set(mesh.cell_data) == {"youngs_modulus", "poisson_ratio"}
    path = tmp_path / "design.vtu"
    report.write(path)
    back = meshio.read(path)
    np.testing.assert_allclose(back.point_data["displacement"], f["displacement"], rtol=1e-15)
    np.testing.assert_allclose(back.cell_data["youngs_modulus"][0], f["youngs_modulus"], rtol=1e-15)
    assert json.loads(report.to_json())["fields"]["design"] == list(z)
