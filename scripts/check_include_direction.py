#!/usr/bin/env python3
"""Checks the dependency direction kernels <- engine <- fem <- io on the sources' includes.

Every project include ("folder/...") of a file under kernels/, engine/, fem/ or io/ must name
its own folder or one below it in that order; tests/ may include the four layers and its own
fixtures, bench/ also the fixture headers of tests/ (a benchmark times the scene a test builds). Exit 1 with one line per upward include (file:line: the include and why it is not
allowed). Run by CTest (label fast) and by hand: scripts/check_include_direction.py [ROOT].
"""
import re
import sys
from pathlib import Path

LAYERS = ["kernels", "engine", "fem", "io"]
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def allowed(source_folder, included_folder, included):
    if source_folder == "tests":
        return included_folder in LAYERS or included_folder == "tests"
    if source_folder == "bench":
        return (included_folder in LAYERS or included_folder == "bench" or
                (included_folder == "tests" and included.endswith(".hpp")))
    if included_folder not in LAYERS:
        return False
    return LAYERS.index(included_folder) <= LAYERS.index(source_folder)


def self_test():
    """The checker on a small tree with one allowed and one upward include: must find one."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        for folder in LAYERS + ["bench", "tests"]:
            (root / folder).mkdir()
        (root / "fem" / "a.hpp").write_text('#include "engine/b.hpp"\n')
        (root / "engine" / "b.hpp").write_text('#include "fem/a.hpp"\n')
        problems = check(root)
    ok = len(problems) == 1 and problems[0].startswith("engine/b.hpp:1")
    print("self-test", "passed" if ok else f"FAILED: {problems}")
    return 0 if ok else 1


def check(root):
    problems = []
    checked = 0
    for folder in LAYERS + ["bench", "tests"]:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".hpp", ".cpp", ".h"):
                continue
            checked += 1
            for number, line in enumerate(path.read_text().splitlines(), start=1):
                m = INCLUDE.match(line)
                if not m or "/" not in m.group(1):
                    continue
                target = m.group(1).split("/")[0]
                if target not in LAYERS + ["bench", "tests"]:
                    continue  # a third-party or generated header
                if not allowed(folder, target, m.group(1)):
                    problems.append(f"{path.relative_to(root)}:{number}: includes "
                                    f"\"{m.group(1)}\": {folder}/ may not depend on {target}/ "
                                    f"(direction {' <- '.join(LAYERS)})")
    print(f"{checked} files checked")
    return problems


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent
    problems = check(root)
    for p in problems:
        print(p)
    print(f"{len(problems)} upward include(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
