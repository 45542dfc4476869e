# Result fields outside the command line: a functional's fields at any design, meshio meshes
# and VTU files written from Python, and matplotlib figures. Reference: the VTU that
# `tailor simulate` itself writes, read back by meshio (a reader nobody here wrote), and the
# report's own arrays.
import numpy as np
import pytest

import tailor
from conftest import scene_path


def test_functional_fields_at_a_design_match_the_state():
    J = tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()
    z = J.x0 + np.array([0.3, -0.2])
    f = J.fields(z)
    np.testing.assert_array_equal(f["displacement"], J.state(z))
    np.testing.assert_array_equal(f["youngs_modulus"], J.youngs_modulus(z))
    point, cell = tailor.fields.split(f)
    assert set(point) == {"displacement"} and set(cell) == {"youngs_modulus"}


def test_meshio_reads_what_the_cli_wrote_and_what_python_writes(tmp_path):
    meshio = pytest.importorskip("meshio", reason="meshio is not installed (Debian: python3-meshio)")
    report = tailor.simulate(str(scene_path("cantilever.json")), out_dir=tmp_path / "cli")
    written = meshio.read(tmp_path / "cli" / "result.vtu")
    u = report.fields["displacement"]
    np.testing.assert_allclose(written.point_data["displacement"][:, : u.shape[1]], u, rtol=1e-12, atol=1e-15)

    mesh = report.to_meshio()
    assert mesh.cells[0].type == "tetra" and len(mesh.cells[0].data) == report.fields["elements"].shape[0]
    tailor.fields.write(report.fields, tmp_path / "python.vtu")
    again = meshio.read(tmp_path / "python.vtu")
    np.testing.assert_array_equal(again.point_data["displacement"], u)
    np.testing.assert_array_equal(again.cell_data["youngs_modulus"][0], report.fields["youngs_modulus"])
    with pytest.raises(ValueError, match="no mesh"):
        tailor.fields.to_meshio({"displacement": u})


def test_plots_of_a_field_and_of_a_history(tmp_path):
    matplotlib = pytest.importorskip("matplotlib", reason="matplotlib is not installed (python3-matplotlib)")
    matplotlib.use("Agg")
    J = tailor.load(str(scene_path("two_material_bar_inverse.json"))).functional()
    ax = tailor.fields.plot(J.fields(J.x0))
    assert len(ax.collections) == 1 and ax.get_title() == "youngs_modulus"
    result = tailor.scipy_minimize(J)
    ax = tailor.fields.plot_history(result.history)
    ax.figure.savefig(tmp_path / "history.png")
    assert (tmp_path / "history.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="not a per-element scalar field"):
        tailor.fields.plot(J.fields(J.x0), name="displacement")
