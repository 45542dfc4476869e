# The bindings run the same scene as the tailor executable: the numbers of the reports they
# write are equal to round-off (reference: the executable's report.json for the same scene),
# and the NumPy fields agree with the report's summary numbers.
import io
import json

import numpy as np
import pytest

import tailor
from conftest import read_json, scene_path, small_dynamic_scene

RTOL = 1e-10


def numbers(value, path=""):
    """Every number in a JSON value with its key path, skipping timings and thread settings."""
    if isinstance(value, dict):
        for key, item in value.items():
            if key in ("timings", "seconds", "threads", "source", "fields") or key.endswith("_seconds"):
                continue
            yield from numbers(item, f"{path}.{key}")
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield from numbers(item, f"{path}[{i}]")
    elif isinstance(value, bool) or value is None or isinstance(value, str):
        yield path, value
    elif isinstance(value, (int, float)):
        yield path, float(value)


def assert_same_report(cli_report, py_report):
    expected = dict(numbers(cli_report))
    got = dict(numbers({k: v for k, v in py_report.items() if k != "fields"}))
    assert len(expected) > 10  # a report with numbers in it, not an empty one
    assert expected.keys() == got.keys()
    for key, value in expected.items():
        if isinstance(value, float):
            assert got[key] == pytest.approx(value, rel=RTOL, abs=1e-12 * max(1.0, abs(value))), key
        else:
            assert got[key] == value, key


def test_simulate_static_matches_cli(cli, tmp_path):
    scene = scene_path("cantilever.json")
    code, output = cli("simulate", scene, tmp_path / "cli")
    assert code == 0, output
    report = tailor.simulate(str(scene), out_dir=tmp_path / "py")
    assert report.ok and report.exit_code == 0
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)
    # The fields against the report's own summary.
    u = report["fields"]["displacement"]
    assert u.shape == (report["mesh"]["vertices"], report["mesh"]["dim"])
    norms = np.linalg.norm(u, axis=1)
    assert norms.max() == pytest.approx(report["results"]["max_displacement"], rel=1e-14)
    assert int(norms.argmax()) == report["results"]["max_displacement_vertex"]
    assert report["fields"]["youngs_modulus"].shape == (report["mesh"]["elements"],)
    assert (report["fields"]["youngs_modulus"] == 1e6).all()  # the scene's one material


def test_scene_from_dict_equals_file(tmp_path):
    path = scene_path("cantilever.json")
    from_file = tailor.simulate(str(path))
    from_dict = tailor.load(read_json(path), directory=path.parent).simulate()
    np.testing.assert_array_equal(from_dict.fields["displacement"], from_file.fields["displacement"])
    assert from_dict["scene"]["source"] == "(scene)"


def test_dynamic_simulate_matches_cli(cli, tmp_path):
    scene = small_dynamic_scene()
    path = tmp_path / "beam.json"
    path.write_text(json.dumps(scene))
    code, output = cli("simulate", path, tmp_path / "cli")
    assert code == 0, output
    report = tailor.load(scene).simulate(out_dir=tmp_path / "py")
    assert report.ok
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)


def test_modes_match_cli(cli, tmp_path):
    scene = scene_path("steel_cantilever_modes.json")
    code, output = cli("modes", scene, tmp_path / "cli", "--count", "4")
    assert code == 0, output
    report = tailor.modes(str(scene), count=4, out_dir=tmp_path / "py")
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)
    np.testing.assert_allclose(report.fields["frequencies"], report["frequencies_hz"], rtol=1e-14)
    assert report.fields["modes"].shape == (3 * report["mesh"]["vertices"], 4)


def test_run_matches_cli(cli, tmp_path):
    scene = scene_path("two_material_bar_inverse.json")
    code, output = cli("run", scene, tmp_path / "cli", "--quiet")
    assert code == 0, output
    report = tailor.run(str(scene), out_dir=tmp_path / "py")
    assert report.ok and report.fields["status"] == "converged"
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)
    # Per-element E: the soft half 1e5, the stiff half 3e5 (the scene's ground truth).
    E = report.fields["youngs_modulus"]
    assert sorted(set(np.round(E / 1e5, 4))) == [1.0, 3.0]


def test_gradcheck_matches_cli(cli, tmp_path):
    scene = scene_path("two_material_bar_inverse.json")
    code, output = cli("gradcheck", scene, tmp_path / "cli", "--hessian")
    assert code == 0, output
    report = tailor.gradcheck(str(scene), hessian=True, out_dir=tmp_path / "py")
    assert report.ok
    assert_same_report(read_json(tmp_path / "cli" / "gradcheck.json"), report)


def test_dynamic_gradcheck_matches_cli(cli, tmp_path):
    # Without an "inverse" section: the time-dependent adjoint of dynamics.objective.
    scene = small_dynamic_scene()
    path = tmp_path / "beam.json"
    path.write_text(json.dumps(scene))
    code, output = cli("gradcheck", path, tmp_path / "cli")
    assert code == 0, output
    report = tailor.load(scene).gradcheck(out_dir=tmp_path / "py")
    assert report.ok and report["passed"]
    assert_same_report(read_json(tmp_path / "cli" / "gradcheck.json"), report)


def test_check_agrees_with_cli(cli):
    scene = scene_path("cantilever.json")
    code, output = cli("check", scene, None)
    assert code == 0, output
    log = io.StringIO()
    assert tailor.load(str(scene)).check(log=log) is True
    assert log.getvalue() == output  # the same tables


def test_file_kind_scene_matches_cli(cli, tmp_path):
    # A kind read by its own reader (rigid bodies in contact): the command line's handler.
    scene = scene_path("contact/box_on_ground.json")
    code, output = cli("simulate", scene, tmp_path / "cli")
    assert code == 0, output
    loaded = tailor.load(str(scene))
    assert loaded.kind == "rigid_bodies"
    report = loaded.simulate(out_dir=tmp_path / "py")
    assert report.ok and report.fields == {}
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)


def test_option_a_kind_cannot_honour_is_a_value_error():
    rods = tailor.load(str(scene_path("rods/rod_stiffness_design.json")))
    with pytest.raises(ValueError, match="--resume and --checkpoint-every are not implemented for rod scenes"):
        rods.run(checkpoint_every=5)


def test_dict_rods_scene_matches_cli(cli, tmp_path):
    # Every kind takes a dict: a rods scene runs the command line's handler on the document.
    path = scene_path("rods/rod_cantilever.json")
    code, output = cli("simulate", path, tmp_path / "cli")
    assert code == 0, output
    loaded = tailor.load(read_json(path), name="rod_cantilever")
    assert loaded.kind == "rods"
    report = loaded.simulate(out_dir=tmp_path / "py")
    assert report.ok and report["status"] == "converged" and report.fields == {}
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)


def test_dict_cell_scene_homogenizes_like_cli(cli, tmp_path):
    document = read_json(scene_path("homogenization/layered_square.json"))
    del document["stress_strain"]  # the linear part only: quicker
    path = tmp_path / "layered.json"
    path.write_text(json.dumps(document))
    code, output = cli("homogenize", path, tmp_path / "cli")
    assert code == 0, output
    loaded = tailor.load(document)
    assert loaded.kind == "periodic_cell"
    report = loaded.homogenize(out_dir=tmp_path / "py")
    assert report.ok and report["status"] == "ok" and report["scene"] == "layered_square"
    assert_same_report(read_json(tmp_path / "cli" / "report.json"), report)
    # A mesh file's path starts from `directory`: a unit square of 3 x 3 squares, two triangles each.
    n = 3
    vertices = [f"{i / n} {j / n} 0" for j in range(n + 1) for i in range(n + 1)]
    triangles = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            triangles += [f"{a} {a + 1} {a + n + 2} 0", f"{a} {a + n + 2} {a + n + 1} 0"]
    (tmp_path / "square.mesh").write_text("\n".join(
        ["MeshVersionFormatted 1", "Dimension 2", "Vertices", str(len(vertices)), *vertices,
         "Triangles", str(len(triangles)), *triangles, "End", ""]))
    square = {"type": "periodic_cell", "cell": {"lattice": [[1, 0], [0, 1]], "mesh": "square.mesh"},
              "plane": "stress", "materials": [{"youngs_modulus": 2, "poisson_ratio": 0.25}], "directions": 8}
    report = tailor.load(square, directory=tmp_path).homogenize(out_dir=tmp_path / "square")
    assert report.ok and report["scene"] == "scene"  # a dict without a name
    assert report["engineering_constants"]["E1"] == pytest.approx(2.0, rel=1e-10)  # homogeneous
    assert report["engineering_constants"]["G12"] == pytest.approx(0.8, rel=1e-10)
