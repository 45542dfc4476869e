# The command line's output goes to `log` line by line (reference: the executable's stdout for
# the same scene), and an exception raised by log.write() comes back as itself.
import io

import pytest

import tailor
from conftest import scene_path


def test_log_has_the_executables_lines(cli, tmp_path):
    scene = scene_path("cantilever.json")
    code, output = cli("simulate", scene, tmp_path / "cli")
    assert code == 0
    log = io.StringIO()
    tailor.simulate(str(scene), out_dir=tmp_path / "py", log=log)
    newton = lambda text: [line for line in text.splitlines() if line.lstrip().startswith("newton")]
    assert newton(log.getvalue()) == newton(output)
    assert len(newton(output)) >= 3


def test_a_failing_write_is_raised():
    log = io.StringIO()
    log.close()
    with pytest.raises(ValueError, match="I/O operation on closed file"):
        tailor.simulate(str(scene_path("cantilever.json")), log=log)
