# tailor.studio (python/tailor/studio.py): starts `tailor studio` as a subprocess and returns the
# URL with its token; the page is served with the token and refused without it. Skipped when the
# program was built without the studio or its page is not built (scripts/build-studio-web.sh).
import os
import pathlib
import subprocess
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


def test_studio_serves_with_its_token(tmp_path):
    executable = os.environ.get("TAILOR_CLI", str(SOURCE_DIR / "build" / "bin" / "tailor"))
    usage = subprocess.run([executable, "--help"], capture_output=True, text=True).stdout
    if "studio SCENE_OR_OUT_DIR" not in usage:
        pytest.skip("tailor was built without the studio (cpp-httplib)")
    assets = pathlib.Path(executable).resolve().parents[1] / "share" / "tailor" / "studio"
    if not (assets / "index.html").is_file() and not os.environ.get("TAILOR_STUDIO_ASSETS"):
        pytest.skip("the studio's page is not built (bash scripts/build-studio-web.sh)")
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
