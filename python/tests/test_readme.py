# The README's Python example runs as printed (in a scratch folder, with the repository's
# scenes), and recovers the moduli its comment states.
import os
import re

import numpy as np

from conftest import SOURCE_DIR


def test_readme_python_example(tmp_path, monkeypatch):
    readme = (SOURCE_DIR / "README.md").read_text()
    section = readme[readme.index("\n## Python\n"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    code = code.replace('"scenes/', f'"{SOURCE_DIR}/scenes/')
    monkeypatch.chdir(tmp_path)
    namespace = {}
    exec(compile(code, "README.md", "exec"), namespace)
    np.testing.assert_allclose(namespace["J"].design_values(namespace["result"].x), [1e5, 3e5], rtol=1e-3)
    assert namespace["report"].ok and os.path.isfile(tmp_path / "out" / "bar" / "report.json")
