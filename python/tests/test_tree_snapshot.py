# tree_snapshot.py, the check behind python.install that `cmake --install` writes nothing into
# the build or source tree: it sees a file added, changed or removed, lets an allowed one pass,
# and skips nested build trees (a folder with a CMakeCache.txt) and .git.
import pathlib
import subprocess
import sys

SNAPSHOT = pathlib.Path(__file__).resolve().parent / "tree_snapshot.py"


def snapshot(*args):
    return subprocess.run([sys.executable, str(SNAPSHOT), *map(str, args)], capture_output=True, text=True)


def test_snapshot_sees_what_changed(tmp_path):
    tree, lists = tmp_path / "tree", tmp_path / "lists"
    (tree / "sub").mkdir(parents=True)
    (tree / "nested_build").mkdir()
    (tree / "nested_build" / "CMakeCache.txt").write_text("")
    (tree / "kept.txt").write_text("a")
    (tree / "sub" / "changed.txt").write_text("a")
    (tree / "removed.txt").write_text("a")
    lists.mkdir()
    assert snapshot("take", lists / "before.json", tree).returncode == 0
    (tree / "sub" / "changed.txt").write_text("bb")
    (tree / "removed.txt").unlink()
    (tree / "added.txt").write_text("a")
    (tree / "manifest.txt").write_text("a")
    (tree / "nested_build" / "ignored.txt").write_text("a")
    assert snapshot("take", lists / "after.json", tree).returncode == 0
    done = snapshot("compare", lists / "before.json", lists / "after.json", "--allow", tree / "manifest.txt")
    assert done.returncode == 1
    assert f"added: {tree / 'added.txt'}\n" in done.stdout
    assert f"changed: {tree / 'sub' / 'changed.txt'}\n" in done.stdout
    assert f"removed: {tree / 'removed.txt'}\n" in done.stdout
    assert f"added: {tree / 'manifest.txt'} (allowed)" in done.stdout
    assert "ignored.txt" not in done.stdout and "kept.txt" not in done.stdout
    # Nothing but the allowed file: passes.
    (tree / "added.txt").unlink()
    (tree / "removed.txt").write_text("a")
    assert snapshot("take", lists / "before.json", tree).returncode == 0
    (tree / "manifest.txt").write_text("bb")
    assert snapshot("take", lists / "after.json", tree).returncode == 0
    assert snapshot("compare", lists / "before.json", lists / "after.json", "--allow",
                    tree / "manifest.txt").returncode == 0
