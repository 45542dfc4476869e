# examples/python/recover_modulus.py runs and reaches what it states (exit 0: the Taylor test
# passes and the recovered field is within 15% of the scene's true field).
import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_recover_modulus_example(tmp_path):
    script = SOURCE_DIR / "examples" / "python" / "recover_modulus.py"
    done = subprocess.run([sys.executable, str(script), "--out", str(tmp_path)], capture_output=True,
                          text=True, env=dict(os.environ), cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Taylor test: passed" in done.stdout
