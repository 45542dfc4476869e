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

