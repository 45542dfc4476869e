"""tailor studio from Python: the same local web server as `tailor studio` (docs/studio.md),
started as a subprocess of the tailor program.

    import tailor
    page = tailor.studio("scenes/cantilever_handle_reduced.json")   # or an output folder
    page            # in Jupyter: the page in an IFrame; elsewhere the URL (a str)
    page.stop()     # ends the server (it also ends with the Python process)

The server ends with the Python process however that ends (a kernel killed or crashed included):
it is started with `--exit-on-stdin-eof` and its standard input is a pipe that only this process
writes to, which the operating system closes when the process ends.
"""
from __future__ import annotations

import atexit
import os
import pathlib
import re
import shutil
import subprocess
import threading

_URL = re.compile(r"(http://127\.0\.0\.1:\d+/[0-9a-f]+/)")
_running: list[subprocess.Popen] = []


class StudioURL(str):
    """The page's URL (with its token). Shown by IPython as an IFrame of the page."""

    process: subprocess.Popen
    width: int = 1000
    height: int = 600

    def _repr_html_(self):
        return (f'<iframe src="{self}" width="{self.width}" height="{self.height}" '
                f'style="border: 1px solid #ccc"></iframe>')

    def stop(self):
        """Ends the server."""
        if self.process.poll() is None:
            self.process.terminate()
            self.process.wait(timeout=10)


def _executable(executable):
    if executable:
        return str(executable)
    if os.environ.get("TAILOR_CLI"):
        return os.environ["TAILOR_CLI"]
    # The build tree (build/python/tailor -> build/bin) and an installed prefix
    # (lib/python3.X/dist-packages/tailor -> bin) alike.
    here = pathlib.Path(__file__).resolve().parent
    for candidate in (here.parents[1] / "bin" / "tailor", here.parents[3] / "bin" / "tailor"):
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return str(candidate)
    found = shutil.which("tailor")
    if not found:
        raise FileNotFoundError("the tailor program was not found: pass executable= or set TAILOR_CLI")
    return found


def studio(path, port: int | None = None, out: str | None = None, executable=None,
           timeout: float = 600.0) -> StudioURL:
    """Starts `tailor studio path` (a scene or an output folder) and returns its URL once the
    server listens (a handle scene first precomputes its reduced design). `port`: a fixed port
    (default a free one); `out`: a scene's output folder. Raises RuntimeError with the program's
    output when it stops before serving."""
    command = [_executable(executable), "studio", str(path), "--exit-on-stdin-eof"]
    if port is not None:
        command += ["--port", str(port)]
    if out is not None:
        command += ["--out", str(out)]
    # stdin: a pipe held open by `process` (close_fds keeps it from other children), so that the
    # server sees its end when this process ends.
    process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, close_fds=True)
    lines: list[str] = []
    found = threading.Event()

    def read():
        for line in process.stdout:
            lines.append(line)
            if _URL.search(line):
                found.set()
        found.set()  # the program ended

    threading.Thread(target=read, daemon=True).start()
    found.wait(timeout)
    match = next((m for m in map(_URL.search, lines) if m), None)
    if not match:
        process.kill()
        raise RuntimeError("tailor studio did not start:\n" + "".join(lines))
    _running.append(process)
    url = StudioURL(match.group(1))
    url.process = process
    return url


@atexit.register
def _stop_all():
    for process in _running:
        if process.poll() is None:
            process.terminate()
