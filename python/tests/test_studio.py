# tailor.studio (python/tailor/studio.py): starts `tailor studio` as a subprocess and returns the
# URL with its token; the page is served with the token and refused without it. Skipped when the
# program was built without the studio or its page is not built (scripts/build-studio-web.sh).
import os
import pathlib
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request

import pytest

import tailor

SOURCE_DIR = pathlib.Path(os.environ.get("TAILOR_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def _status(url):
    try:
        with urllib.request.urlopen(url, timeout=30) as response:
            return response.status
    except urllib.error.HTTPError as error:
        return error.code


def _studio_executable():
    executable = os.environ.get("TAILOR_CLI", str(SOURCE_DIR / "build" / "bin" / "tailor"))
    usage = subprocess.run([executable, "--help"], capture_output=True, text=True).stdout
    if "studio SCENE_OR_OUT_DIR" not in usage:
        pytest.skip("tailor was built without the studio (cpp-httplib)")
    assets = pathlib.Path(executable).resolve().parents[1] / "share" / "tailor" / "studio"
    if not (assets / "index.html").is_file() and not os.environ.get("TAILOR_STUDIO_ASSETS"):
        pytest.skip("the studio's page is not built (bash scripts/build-studio-web.sh)")
    return executable


def _alive(pid):
    # A zombie (ended, not yet reaped by its new parent) counts as ended.
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def _ends_within(pid, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if not _alive(pid):
            return True
        time.sleep(0.05)
    return False


def _start_under(parent_command, tmp_path):
    """Runs `parent_command` (which starts a studio server and prints its pid as the first line,
    then waits) and returns (parent, server pid)."""
    parent = subprocess.Popen(parent_command, stdout=subprocess.PIPE, text=True,
                              env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    line = parent.stdout.readline()
    assert line.strip().isdigit(), f"the parent printed {line!r}"
    return parent, int(line)


def test_studio_ends_when_the_python_process_is_killed(tmp_path):
    # A notebook kernel killed (SIGKILL: no atexit, no signal handler) takes its server along:
    # tailor.studio starts it with --exit-on-stdin-eof on a pipe only the kernel holds.
    executable = _studio_executable()
    script = ("import sys, time, tailor\n"
              f"page = tailor.studio({str(tmp_path)!r}, executable={executable!r}, timeout=60)\n"
              "print(page.process.pid, flush=True)\n"
              "time.sleep(600)\n")
    parent, server = _start_under([sys.executable, "-c", script], tmp_path)
    try:
        time.sleep(0.5)
        assert _alive(server), "the server ended while its starter lives"
        parent.send_signal(signal.SIGKILL)
        parent.wait(timeout=10)
        assert _ends_within(server, 5), "the server outlived the Python process that started it"
    finally:
        if _alive(server):
            os.kill(server, signal.SIGKILL)


def test_studio_exit_with_parent_ends_with_a_killed_shell(tmp_path):
    # A shell that starts the server in the background and is killed: --exit-with-parent notices
    # the reparenting. Without the flag the server would live on (checked first, so that the
    # check can fail).
    executable = _studio_executable()
    for flag, should_end in (("", False), ("--exit-with-parent", True)):
        shell = f'"$0" studio "$1" {flag} >/dev/null 2>&1 & echo $!; wait'
        parent, server = _start_under(["sh", "-c", shell, executable, str(tmp_path)], tmp_path)
        try:
            time.sleep(1.0)
            assert _alive(server)
            parent.send_signal(signal.SIGKILL)
            parent.wait(timeout=10)
            assert _ends_within(server, 5) == should_end, f"{flag or 'no flag'}: the server " + (
                "outlived its parent" if should_end else "ended without the flag")
        finally:
            if _alive(server):
                os.kill(server, signal.SIGKILL)


def test_studio_serves_with_its_token(tmp_path):
    executable = _studio_executable()
    (tmp_path / "report.json").write_text("{}")
    page = tailor.studio(tmp_path, executable=executable, timeout=60)
    try:
        assert page.startswith("http://127.0.0.1:") and page.endswith("/")
        token = page.rstrip("/").rsplit("/", 1)[1]
        assert len(token) == 32
        assert _status(page) == 200
        assert _status(page + "files/report.json") == 200
        origin = page[: page.index("/", len("http://"))]
        assert _status(origin + "/files/report.json") == 403
        assert "<iframe" in page._repr_html_()
    finally:
        page.stop()
    assert page.process.poll() is not None
