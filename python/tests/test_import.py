# An interpreter that cannot load the compiled module (another Python, no NumPy) is told which
# interpreter the module was built for. Simulated with a copy of the package without _tailor.
import os
import pathlib
import shutil
import subprocess
import sys

import tailor


def test_an_import_that_cannot_load_the_module_names_the_interpreter_it_was_built_for(tmp_path):
    package = pathlib.Path(tailor.__file__).parent
    copy = tmp_path / "tailor"
    copy.mkdir()
    for file in package.glob("*.py"):
        shutil.copy(file, copy)
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    done = subprocess.run([sys.executable, "-c", "import tailor"], capture_output=True, text=True, env=env,
                          cwd=tmp_path)
    assert done.returncode != 0
    assert "tailor's compiled module was built for Python 3." in done.stderr, done.stderr
    assert f"this is Python {sys.version_info[0]}.{sys.version_info[1]} ({sys.executable})" in done.stderr
    assert "-DPython3_EXECUTABLE=" in done.stderr
