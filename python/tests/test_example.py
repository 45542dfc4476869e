# examples/python/recover_modulus.py runs and reaches what it states (exit 0: the Taylor test
# passes and the recovered field is within 15% of the scene's true field).
import os
import subprocess
import sys

import tailor
from conftest import SOURCE_DIR


def test_recover_modulus_example(tmp_path):
    script = SOURCE_DIR / "examples" / "python" / "recover_modulus.py"
    # The package these tests import, also when PYTHONPATH was given relative to another folder.
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(os.path.abspath(tailor.__file__))))
    done = subprocess.run([sys.executable, str(script), "--out", str(tmp_path)], capture_output=True,
                          text=True, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Taylor test: passed" in done.stdout


def test_torch_neural_field_example(tmp_path):
    # examples/python/torch_neural_field.py trains a network's weights through the simulator
    # (tailor.torch.state: Newton forward, adjoint backward); it exits non-zero unless the
    # displacement misfit falls 100-fold and E ends closer to the truth than the uniform start.
    import pytest
    pytest.importorskip("torch", reason="PyTorch (python3-torch) is not installed")
    script = SOURCE_DIR / "examples" / "python" / "torch_neural_field.py"
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(os.path.abspath(tailor.__file__))))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "neural field: reached" in done.stdout
