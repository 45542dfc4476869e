"""What `cmake --install` wrote outside its prefix (python.install, install_check.cmake).

    tree_snapshot.py take OUT.json ROOT...      every file under each ROOT: size and mtime
    tree_snapshot.py compare BEFORE AFTER [--allow NAME]...

take skips .git and every folder with a CMakeCache.txt below a ROOT (another build tree, such
as the build folder inside the source tree, has its own snapshot or none) and a ROOT's
Testing/ folder (ctest's own logs, written while the test runs). compare prints each file added,
removed or changed and exits 1 if any is not allowed (NAME: a path as listed, ROOT/relative).
"""
import json
import os
import sys


def take(roots):
    files = {}
    for root in roots:
        root = os.path.abspath(root)
        for folder, subfolders, names in os.walk(root):
            keep = []
            for sub in subfolders:
                path = os.path.join(folder, sub)
                if sub == ".git" or os.path.isfile(os.path.join(path, "CMakeCache.txt")):
                    continue
                if folder == root and sub == "Testing":
                    continue
                keep.append(sub)
            subfolders[:] = keep
            for name in names:
                path = os.path.join(folder, name)
                try:
                    s = os.lstat(path)
                except FileNotFoundError:  # removed while listed
                    continue
                files[path] = [s.st_size, s.st_mtime_ns]
    return files


def main(argv):
    if len(argv) >= 3 and argv[0] == "take":
        with open(argv[1], "w") as f:
            json.dump(take(argv[2:]), f)
        return 0
    if len(argv) >= 3 and argv[0] == "compare":
        with open(argv[1]) as f:
            before = json.load(f)
        with open(argv[2]) as f:
            after = json.load(f)
        allowed = {os.path.abspath(a) for flag, a in zip(argv[3::2], argv[4::2]) if flag == "--allow"}
        changed = sorted(set(before) ^ set(after) | {p for p in set(before) & set(after) if before[p] != after[p]})
        bad = [p for p in changed if p not in allowed]
        for path in changed:
            state = "added" if path not in before else "removed" if path not in after else "changed"
            print(f"{state}: {path}{'' if path in bad else ' (allowed)'}")
        return 1 if bad else 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
