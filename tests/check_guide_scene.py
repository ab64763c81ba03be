#!/usr/bin/env python3
"""The dynamic scene docs/guide.md works through is the program CTest runs, verbatim.

Takes the lines between `// ---- scene` and `// ---- end of scene` of tests/guide/sliding_table.cpp
(the CTest guide_sliding_table, which checks them against their closed forms) and fails unless
docs/guide.md holds them as one block, so the guide's listing cannot drift from the tested code.

Usage: check_guide_scene.py ROOT
"""
import os
import sys


def main():
    root = sys.argv[1]
    with open(os.path.join(root, "tests", "guide", "sliding_table.cpp"), encoding="utf-8") as f:
        program = f.read()
    start, end = "// ---- scene\n", "// ---- end of scene"
    if start not in program or end not in program:
        print("tests/guide/sliding_table.cpp: the markers '%s' and '%s' are missing" % (start.strip(), end))
        return 1
    scene = program.split(start, 1)[1].split(end, 1)[0].rstrip("\n")
    with open(os.path.join(root, "docs", "guide.md"), encoding="utf-8") as f:
        guide = f.read()
    if "```cpp\n" + scene + "\n```" not in guide:
        print("docs/guide.md does not hold the scene of tests/guide/sliding_table.cpp verbatim "
              "(%d lines between its markers); copy them into the guide's listing" % len(scene.splitlines()))
        return 1
    print("docs/guide.md holds the %d lines of tests/guide/sliding_table.cpp's scene" % len(scene.splitlines()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
