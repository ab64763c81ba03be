#!/usr/bin/env python3
"""README.md's C++ block is tests/consumer/arch.cpp verbatim (the program package_consumer
compiles and runs against the installed package), so the front page cannot drift from code
that builds. Usage: check_readme_program.py <source dir>. Exit 1 naming the first line that
differs."""
import difflib
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1])
readme = (root / "README.md").read_text()
program = (root / "tests/consumer/arch.cpp").read_text()
blocks = re.findall(r"```cpp\n(.*?)```", readme, re.S)
if len(blocks) != 1:
    sys.exit(f"README.md has {len(blocks)} ```cpp blocks, expected exactly one (tests/consumer/arch.cpp)")
if blocks[0] != program:
    diff = difflib.unified_diff(program.splitlines(True), blocks[0].splitlines(True),
                                "tests/consumer/arch.cpp", "README.md ```cpp block", n=1)
    sys.stdout.writelines(list(diff)[:30])
    sys.exit("README.md's C++ block differs from tests/consumer/arch.cpp: copy the program into the README")
print("README.md's C++ block is tests/consumer/arch.cpp")
