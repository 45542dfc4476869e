# Bad input is a ValueError (tailor.SceneError) whose message is the C++ one: the scene's name,
# the key path, for a broken file the line and column; failures to write are RuntimeErrors.
import json

import numpy as np
import pytest

import tailor
from conftest import read_json, scene_path


def cantilever():
    return read_json(scene_path("cantilever.json"))


def test_bad_value_names_the_key_path():
    scene = cantilever()
    scene["materials"][0]["youngs_modulus"] = -1
    message = r"^\(scene\): materials\[0\]\.youngs_modulus: expected a number > 0, got -1$"
    with pytest.raises(ValueError, match=message):
        tailor.load(scene).simulate()


def test_scene_error_is_a_value_error_with_the_given_name():
    scene = cantilever()
    scene["mesh"]["box"]["cells"][2] = "x"
    with pytest.raises(tailor.SceneError, match=r"^bar: mesh\.box\.cells\[2\]: expected an integer >= 1"):
        tailor.load(scene, name="bar").simulate()
    assert issubclass(tailor.SceneError, ValueError)


def test_unknown_key():
    scene = cantilever()
    scene["materails"] = []
    with pytest.raises(ValueError, match=r"materails: unknown key"):
        tailor.load(scene).simulate()


def test_broken_file_names_line_and_column(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text('{\n  "mesh": [1,\n  }\n')
    with pytest.raises(ValueError, match=rf"^{path}: invalid JSON .*line 3, column 3"):
        tailor.load(str(path))


def test_missing_file():
    with pytest.raises(ValueError, match="cannot open the scene file"):
        tailor.load("no/such/scene.json")


def test_verbs_that_need_an_inverse_section():
    scene = tailor.load(str(scene_path("cantilever.json")))
    message = r'cantilever\.json: \(top level\): the scene has no "inverse" section'
    with pytest.raises(ValueError, match=message):
        scene.gradcheck()
    with pytest.raises(ValueError, match=r'the scene has no "inverse" section'):
        scene.run()
    with pytest.raises(ValueError, match=r'the scene has no "inverse" section'):
        scene.functional()


def test_functional_of_another_kind_names_the_supported_ones():
    with pytest.raises(tailor.SceneError, match=r"box_drop\.json: functional\(\) needs a static FEM, a rods "
                       r"or a meshless scene with an \"inverse\" section, a dynamic scene with a dynamics\.objective, "
                       r"or a periodic cell with a \"design\" section; this is a rigid_bodies scene"):
        tailor.load(str(scene_path("contact/box_drop.json"))).functional()


def test_bad_inverse_key_path_in_functional():
    scene = read_json(scene_path("two_material_bar_inverse.json"))
    scene["inverse"]["design"]["min"] = 0
    with pytest.raises(ValueError, match=r"inverse\.design\.min: with the log map"):
        tailor.load(scene).functional()


def test_not_json_values_and_types():
    with pytest.raises(ValueError, match="not JSON compliant"):
        tailor.load({"mesh": float("nan")})
    with pytest.raises(TypeError):
        tailor.load(42)


def test_unwritable_output_is_a_runtime_error(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    with pytest.raises(RuntimeError, match="cannot create the output folder"):
        tailor.simulate(str(scene_path("cantilever.json")), out_dir=blocker / "out")


def test_dict_scenes_of_every_kind_name_the_key():
    # A dict scene of a kind other than static or dynamic is parsed by that kind: the error names
    # the scene's name and the key path.
    with pytest.raises(tailor.SceneError, match=r"my rods: rods: expected an array, got an object"):
        tailor.load({"rods": {}}, name="my rods").simulate()
    cell = {"type": "periodic_cell", "cell": {"lattice": [[1, 0], [0, 1]], "grid": [2, 2], "gird": 1},
            "materials": [{"youngs_modulus": 1, "poisson_ratio": 0.3}]}
    with pytest.raises(tailor.SceneError, match=r"\(scene\): cell\.gird: unknown key"):
        tailor.load(cell).homogenize()


def test_bad_mesh_file_is_a_mesh_error_with_file_and_line(tmp_path):
    # A dict scene's relative paths start from `directory`.
    (tmp_path / "bad.msh").write_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 x\n")
    scene = cantilever()
    scene["mesh"] = {"file": "bad.msh"}
    with pytest.raises(tailor.MeshError, match=r"bad\.msh:6: expected node coordinate \(a number\), found 'x'"):
        tailor.load(scene, directory=tmp_path).simulate()
    assert issubclass(tailor.MeshError, ValueError)
