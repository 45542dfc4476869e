# The meshless scene kind through tailor.load: simulate(), modes() and gradcheck() run the
# command line's handler on the document (a dict or a file) and return its report; the report
# matches the command line's own, and the gradient's Taylor test converges at rate 2.
import json

import pytest

import tailor
from conftest import read_json

# A 3 x 1 x 1 bar of MLS nodes (h = 0.5, 63 nodes), linear material, clamped at x = 0, a tip
# force; the Young's modulus per node is the design of its inverse section.
BAR = {
    "meshless": {"shape": {"box": {"lo": [0, 0, 0], "hi": [3, 1, 1]}}, "spacing": 0.5, "quadrature_order": 2,
                 "boundary_depth": 0},
    "material": {"model": "linear", "youngs_modulus": 1000, "poisson_ratio": 0.3, "density": 1},
    "fixed": [{"box": {"lo": [-1, -1, -1], "hi": [0, 2, 2]}}],
    "loads": {"forces": [{"at": [3, 0.5, 0.5], "force": [0, 0, -1]}]},
    "modes": {"count": 4},
    "inverse": {"design": "youngs_modulus", "per": "node",
                "observations": [{"at": [3, 0.5, 0.5], "displacement": [0, 0, -0.05]}]},
}


def test_meshless_simulate_matches_the_cli(cli, tmp_path):
    scene = tailor.load(BAR, name="bar")
    assert scene.kind == "meshless"
    report = scene.simulate(out_dir=tmp_path / "python")
    assert report.ok
    assert report["converged"]
    assert report["discretization"]["nodes"] == 63
    # Timoshenko's tip deflection of this bar is 0.1118; the coarse meshless bar lands within 15%.
    assert report["max_sample_displacement"] == pytest.approx(0.1118, rel=0.15)
    assert (tmp_path / "python" / "nodes.vtu").is_file()
    path = tmp_path / "bar.json"
    path.write_text(json.dumps(BAR))
    code, output = cli("simulate", path, tmp_path / "cli")
    assert code == 0, output
    assert read_json(tmp_path / "cli" / "report.json")["max_sample_displacement"] == pytest.approx(
        report["max_sample_displacement"], rel=1e-12)


def test_meshless_modes_and_gradcheck(tmp_path):
    scene = tailor.load(BAR, name="bar")
    modes = scene.modes(count=4, out_dir=tmp_path / "modes")
    assert modes.ok
    frequencies = modes["frequencies"]
    assert len(frequencies) == 4
    # The square section: two equal first bending frequencies.
    assert frequencies[0] == pytest.approx(frequencies[1], rel=1e-6)
    check = scene.gradcheck(out_dir=tmp_path / "gradcheck")
    assert check.ok
    assert check["rate1"] >= 1.9



def test_meshless_modes_give_arrays(tmp_path):
    # modes()' arrays: the report's frequencies; each mode's MLS displacement at the nodes (zero
    # at the clamped ones, where the transformation method holds the field) and at the samples,
    # which is modes.vtu's mode_j.
    import numpy as np
    report = tailor.load(BAR, name="bar").modes(count=4, out_dir=tmp_path)
    f = report.fields
    np.testing.assert_allclose(f["frequencies"], report["frequencies"], rtol=1e-14)
    np.testing.assert_allclose(f["damping_ratios"], report["damping_ratios"], rtol=1e-14)
    assert f["rest_positions"].shape == (63, 3)
    assert f["modes"].shape == (3 * 63, 4)
    assert f["rigid_modes"] == 0
    u = f["modes"].reshape(63, 3, 4)
    clamped = f["rest_positions"][:, 0] < 1e-9
    assert clamped.sum() == 9
    assert np.abs(u[clamped]).max() < 1e-10 * np.abs(u).max()
    # The first two (bending about y and z) move the free end most.
    tip = f["rest_positions"][:, 0] > 3 - 1e-9
    assert np.abs(u[tip, :, 0]).max() == pytest.approx(np.abs(u[:, :, 0]).max())
    m = f["samples"].shape[0]
    assert f["sample_modes"].shape == (3 * m, 4)
    meshio = pytest.importorskip("meshio", reason="meshio is not installed (python3-meshio)")
    points = meshio.read(tmp_path / "modes.vtu")
    np.testing.assert_allclose(points.points, f["samples"], rtol=0, atol=1e-9)  # the file's ten digits
    for j in range(4):
        np.testing.assert_allclose(points.point_data[f"mode_{j + 1}"].reshape(-1), f["sample_modes"][:, j],
                                   rtol=0, atol=1e-8 * np.abs(f["sample_modes"]).max())
    # Held by a handle only, the body's six rigid modes join the warped dynamics' basis but not
    # the arrays or modes.vtu, whose mode_1 is the first elastic mode (it was a rigid one before).
    free = json.loads(json.dumps(BAR))
    free.pop("fixed")
    free.pop("inverse")
    free["handles"] = [{"box": {"lo": [-1, -1, -1], "hi": [0, 2, 2]}, "displacement": [0, 0, 0]}]
    report = tailor.load(free, name="bar").modes(count=4, out_dir=tmp_path / "free")
    f = report.fields
    assert f["rigid_modes"] == 6 and f["modes"].shape == (3 * 63, 4)
    assert f["frequencies"][0] > 0
    mode_1 = meshio.read(tmp_path / "free" / "modes.vtu").point_data["mode_1"].reshape(-1)
    np.testing.assert_allclose(mode_1, f["sample_modes"][:, 0], rtol=0, atol=1e-8 * np.abs(f["sample_modes"]).max())


def test_meshless_simulate_fields_match_the_clis_point_files(cli, tmp_path):
    # simulate()'s arrays against the VTU files and the report `tailor simulate` writes.
    meshio = pytest.importorskip("meshio", reason="meshio is not installed (python3-meshio)")
    import numpy as np

    report = tailor.load(BAR, name="bar").simulate(out_dir=tmp_path / "python")
    f = report.fields
    assert f["rest_positions"].shape == (63, 3) and f["displacement"].shape == (63, 3)
    assert f["coefficient_displacement"].shape == (63, 3) and f["youngs_modulus"].shape == (63,)
    assert f["samples"].shape == f["sample_displacement"].shape == (192, 3)
    np.testing.assert_array_equal(f["positions"], f["rest_positions"] + f["displacement"])
    np.testing.assert_array_equal(f["youngs_modulus"], 1000)
    path = tmp_path / "bar.json"
    path.write_text(json.dumps(BAR))
    code, output = cli("simulate", path, tmp_path / "cli")
    assert code == 0, output
    samples = meshio.read(tmp_path / "cli" / "samples.vtu")
    np.testing.assert_allclose(samples.points, f["samples"], rtol=1e-9)  # the VTU holds 10 digits
    np.testing.assert_allclose(samples.point_data["displacement"], f["sample_displacement"], rtol=1e-9, atol=1e-14)
    largest = np.linalg.norm(f["sample_displacement"], axis=1).max()
    assert read_json(tmp_path / "cli" / "report.json")["max_sample_displacement"] == pytest.approx(largest, rel=1e-12)
    nodes = meshio.read(tmp_path / "cli" / "nodes.vtu")
    for name in ("displacement", "coefficient_displacement", "youngs_modulus"):
        np.testing.assert_allclose(nodes.point_data[name].reshape(f[name].shape), f[name], rtol=1e-9, atol=1e-14)
    # The field at the nodes is the shape functions' combination of the coefficients: at the tip
    # node (3, 0.5, 0.5), where the force acts, its value equals the field the samples interpolate
    # there to the Newton tolerance, and neither equals the node's own coefficient.
    tip = np.flatnonzero(np.all(np.isclose(f["rest_positions"], [3, 0.5, 0.5]), axis=1))[0]
    assert abs(f["displacement"][tip, 2] - f["coefficient_displacement"][tip, 2]) > 1e-4 * abs(f["displacement"][tip, 2])
    # The functional at z0 solves the same equilibrium.
    J = tailor.load(BAR, name="bar").functional()
    np.testing.assert_allclose(J.state(J.x0), f["displacement"], rtol=0, atol=1e-9 * np.abs(f["displacement"]).max())
    # The nodes as a point set through meshio (one vertex cell each), written and read back.
    report.write(tmp_path / "nodes_again.vtu")
    again = meshio.read(tmp_path / "nodes_again.vtu")
    assert again.cells[0].type == "vertex" and len(again.cells[0].data) == 63
    np.testing.assert_array_equal(again.point_data["displacement"], f["displacement"])
    np.testing.assert_array_equal(again.point_data["youngs_modulus"], f["youngs_modulus"])
    assert "sample_displacement" not in again.point_data


def test_modes_handle_stiffness_is_a_scene_key(tmp_path):
    # The bar held by nothing but a 90-degree rotation handle at x = 0 in the warped modal
    # dynamics (as MeshlessScene.RotationHandleTurnsTheWarpedModalBody): the springs' stiffness,
    # k = modes.handle_stiffness times the largest modal eigenvalue, sets how closely the
    # handle's nodes reach their targets.
    document = json.loads(json.dumps(BAR))
    document.pop("fixed")
    document.pop("inverse")
    document["modes"] = {"count": 4, "rayleigh": {"alpha": 4.0, "beta": 0.001}, "steps": 300, "frame_every": 300}
    document["handles"] = [{"box": {"lo": [-1, -1, -1], "hi": [0, 2, 2]}, "rotation": {"axis": [0, 0, 1], "degrees": 90}}]

    def warped(stiffness=None):
        d = json.loads(json.dumps(document))
        if stiffness is not None:
            d["modes"]["handle_stiffness"] = stiffness
        report = tailor.load(d, name="bar").modes(count=4, out_dir=tmp_path / f"k{stiffness}")
        assert report.ok
        return report["warped_dynamics"]

    default, explicit, soft = warped(), warped(1e4), warped(3.0)
    # The default is 1e4, as before the key existed.
    assert default["handle_stiffness"] == explicit["handle_stiffness"]
    assert default["handle_position_error"] == explicit["handle_position_error"] < 1e-6
    # Springs only 3 times the stiffest mode leave the handle visibly off its targets.
    assert soft["handle_stiffness"] == pytest.approx(3e-4 * default["handle_stiffness"], rel=1e-12)
    assert soft["handle_position_error"] > 1e3 * default["handle_position_error"]
    for bad, message in ((0, r"modes\.handle_stiffness: expected a number > 0"),
                         ("stiff", r"modes\.handle_stiffness")):
        d = json.loads(json.dumps(document))
        d["modes"]["handle_stiffness"] = bad
        with pytest.raises(tailor.SceneError, match=message):
            tailor.load(d, name="bar").modes(count=4)
    d = json.loads(json.dumps(document))
    d["modes"]["handle_stifness"] = 1e4
    with pytest.raises(tailor.SceneError, match=r"bar: modes\.handle_stifness: unknown key"):
        tailor.load(d, name="bar").modes(count=4)
