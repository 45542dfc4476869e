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


def test_cpu_core_follows_the_flags_as_the_executable_does():
    avx512 = {"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl", "avx2", "fma"}
    assert tailor._blas_core.cpu_core(avx512) == "SkylakeX"
    assert tailor._blas_core.cpu_core(avx512 - {"avx512vl"}) == "Haswell"
    assert tailor._blas_core.cpu_core({"avx2", "fma", "sse3"}) == "Haswell"
    assert tailor._blas_core.cpu_core({"avx", "sse3"}) is None


def test_python_and_the_executable_run_the_same_blas_kernels(tmp_path):
    # A fresh interpreter without OPENBLAS_CORETYPE: importing tailor first chooses the kernels
    # (tailor/_blas_core.py); bin/tailor chooses them by re-executing itself. On a CPU where
    # OpenBLAS falls back to SSE kernels the two must agree, or the same scene gives results that
    # differ in the last digits between Python and the command line.
    from conftest import read_json, scene_path

    scene = scene_path("two_material_bar_inverse.json")
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "TAILOR_BLAS_REEXEC")}
    script = ("import tailor, sys; r = tailor.load(sys.argv[1]).simulate(out_dir=sys.argv[2]); "
              "print(r['threads']['blas_core'])")
    done = subprocess.run([sys.executable, "-c", script, str(scene), str(tmp_path / "py")], capture_output=True,
                          text=True, env=env)
    assert done.returncode == 0, done.stderr
    python_core = done.stdout.strip().splitlines()[-1]
    executable = os.environ.get("TAILOR_CLI", "tailor")
    done = subprocess.run([executable, "simulate", str(scene), "--out", str(tmp_path / "cli")],
                          capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    assert read_json(tmp_path / "cli" / "report.json")["threads"]["blas_core"] == python_core
