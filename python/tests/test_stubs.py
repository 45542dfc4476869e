# The type stubs of the compiled module (tailor/_tailor.pyi) match it: mypy's stubtest (Debian
# python3-mypy) imports the built module and compares every name and signature. The check is
# shown to fail on a stub with one method misnamed. Skipped where mypy is not installed.
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

import tailor

HERE = pathlib.Path(__file__).resolve().parent


def stubtest(package_parent, tmp_path):
    pytest.importorskip("mypy.stubtest", reason="mypy is not installed (Debian: python3-mypy)")
    config = tmp_path / "mypy.ini"
    config.write_text("[mypy]\nignore_missing_imports = True\ncache_dir = /dev/null\n")
    env = dict(os.environ, PYTHONPATH=str(package_parent))
    return subprocess.run([sys.executable, "-m", "mypy.stubtest", "--mypy-config-file", str(config),
                           "--allowlist", str(HERE / "stubtest_allowlist.txt"), "tailor._tailor"],
                          capture_output=True, text=True, env=env, cwd=tmp_path)


def test_stubs_match_the_compiled_module(tmp_path):
    package = pathlib.Path(tailor.__file__).parent
    done = stubtest(package.parent, tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr


def test_stubtest_sees_a_misnamed_method(tmp_path):
    package = pathlib.Path(tailor.__file__).parent
    copy = tmp_path / "copy" / "tailor"
    shutil.copytree(package, copy)
    stub = copy / "_tailor.pyi"
    stub.write_text(stub.read_text().replace("def vjp(", "def vjp_misnamed("))
    done = stubtest(copy.parent, tmp_path)
    assert done.returncode != 0
    assert "vjp_misnamed" in done.stdout
