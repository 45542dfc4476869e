# Shared by the tests of the Python module. ctest runs them with PYTHONPATH=build/python and
# TAILOR_CLI=build/bin/tailor; run by hand:
#   PYTHONPATH=build/python TAILOR_CLI=build/bin/tailor python3 -m pytest python/tests
import json
import os
import pathlib
import subprocess

import pytest

import tailor  # noqa: F401  (first, so that OpenBLAS loads with the kernels tailor chooses: docs/performance.md)

SOURCE_DIR = pathlib.Path(os.environ.get("TAILOR_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SCENES = SOURCE_DIR / "scenes"


@pytest.fixture(scope="session")
def cli():
    """Runs the tailor executable: cli(verb, scene, out_dir, *flags) -> (exit code, output);
    out_dir None: no --out."""
    executable = os.environ.get("TAILOR_CLI", str(SOURCE_DIR / "build" / "bin" / "tailor"))
    if not os.path.isfile(executable):
        pytest.fail(f"the tailor executable {executable} is missing (set TAILOR_CLI)")

    def run(verb, scene, out_dir, *flags):
        out = [] if out_dir is None else ["--out", str(out_dir)]
        command = [executable, verb, str(scene), *out, *flags]
        done = subprocess.run(command, capture_output=True, text=True)
        return done.returncode, done.stdout + done.stderr

    return run


def read_json(path):
    with open(path) as f:
        return json.load(f)


def scene_path(name):
    return SCENES / name


def small_dynamic_scene():
    """The swinging beam of scenes/swinging_beam.json on a coarser mesh, for 10 steps."""
    scene = read_json(SCENES / "swinging_beam.json")
    scene["name"] = "small_swinging_beam"
    scene["mesh"]["box"]["cells"] = [8, 1, 1]
    scene["dynamics"]["steps"] = 10
    scene["dynamics"]["objective"]["steps"] = [5, 10]
    return scene


def assert_taylor_of_state_loss(loss, state, z, dz, gradient, first_step):
    """The Taylor test of a loss of the state, loss(state(z)), whose design gradient at z is
    `gradient`: over five halvings from first_step the zeroth-order remainder falls at rate 1
    (the asymptotic regime) and the first-order one at >= 1.9; the same gradient 5% off falls at
    rate about 1 at the smallest steps (the test sees an error)."""
    import numpy as np

    value = loss(state(z))
    steps = [first_step / 2**k for k in range(5)]
    losses = [loss(state(z + h * dz)) for h in steps]
    r0 = [abs(L - value) for L in losses]
    r1 = [abs(L - value - h * gradient @ dz) for L, h in zip(losses, steps)]
    rate0 = [np.log2(a / b) for a, b in zip(r0, r0[1:])]
    rate1 = [np.log2(a / b) for a, b in zip(r1, r1[1:])]
    assert min(rate0) > 0.8 and max(rate0) < 1.2, rate0
    assert min(rate1) >= 1.9, rate1
    r_bad = [abs(L - value - 1.05 * h * gradient @ dz) for L, h in zip(losses, steps)]
    assert np.log2(r_bad[-2] / r_bad[-1]) < 1.5
