# Ctrl-C (SIGINT to the process) during a long call: a forward solve stops at its next line of
# output with KeyboardInterrupt (reference: it has not written its report, which it writes at the
# end); an optimization stops itself and still writes its report, with status "interrupted".
import json
import os
import signal
import threading
import time

import pytest

import tailor
from conftest import read_json, scene_path


def interrupt_after(seconds):
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_stops_a_forward_solve(tmp_path):
    scene = read_json(scene_path("cantilever.json"))
    scene["mesh"]["box"]["cells"] = [80, 8, 8]  # about 3 s of Newton iterations
    timer = interrupt_after(0.3)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        tailor.load(scene).simulate(out_dir=tmp_path)
    elapsed = time.monotonic() - start
    timer.join()
    assert not (tmp_path / "report.json").exists()
    assert elapsed < 2.5


class InterruptAtIteration:
    """A log that sends SIGINT to the process when the optimizer prints iteration `at`: from
    inside the optimization, as a Ctrl-C would arrive."""

    def __init__(self, at):
        self.at, self.lines = at, []

    def write(self, text):
        self.lines.append(text)
        fields = text.split()
        if fields and fields[0] == str(self.at) and len(fields) == 7:
            os.kill(os.getpid(), signal.SIGINT)


def test_ctrl_c_stops_an_optimization_with_its_report(tmp_path):
    # Without the interrupt this run converges after 16 iterations (test_cli_parity).
    log = InterruptAtIteration(2)
    report = tailor.load(str(scene_path("two_material_bar_inverse.json"))).run(out_dir=tmp_path, log=log)
    assert report.fields["status"] == "interrupted"
    assert report["status"] == "interrupted" and not report.ok
    assert 2 <= report["iterations"] <= 4
    assert json.loads((tmp_path / "report.json").read_text())["status"] == "interrupted"
    # Python's own handler is back: a Ctrl-C now is a KeyboardInterrupt again.
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1)
