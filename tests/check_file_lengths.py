#!/usr/bin/env python3
"""No file in include/ or examples/ is longer than 500 lines (issue #42: a room a reader holds in mind).

Counts the lines of every text file under ROOT/include and ROOT/examples and fails, naming each
file and its count, when one has more than LIMIT lines. A long file is split by job (one header
per job, the old header including the new ones), not by line count.

PENDING names the files whose split is under way (issue #42); they are listed but do not fail the
check. An entry whose file is no longer over the limit is reported as done, so it can be deleted:
the list only shrinks, and once it is empty every file is held to the limit.

Usage: check_file_lengths.py ROOT
"""
import os
import sys

LIMIT = 500
DIRS = ["include", "examples"]
# Relative to ROOT, with '/' separators.
PENDING = set()


def line_count(path):
    """Lines of a text file (a last line without a newline counts), or None for a binary file."""
    with open(path, "rb") as f:
        data = f.read()
    if b"\0" in data:
        return None
    return data.count(b"\n") + (1 if data and not data.endswith(b"\n") else 0)


def main(root):
    over, pending_over, checked = [], [], 0
    for top in DIRS:
        for dirpath, dirnames, files in os.walk(os.path.join(root, top)):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
            for name in sorted(files):
                if name.startswith("."):
                    continue
                path = os.path.join(dirpath, name)
                n = line_count(path)
                if n is None:
                    continue
                checked += 1
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                if n > LIMIT:
                    (pending_over if rel in PENDING else over).append((rel, n))
    for rel, n in over:
        print(f"check_file_lengths: {rel} has {n} lines > {LIMIT}; split it by job (issue #42)")
    for rel, n in pending_over:
        print(f"check_file_lengths: pending: {rel} has {n} lines > {LIMIT} (its split is under way)")
    still = {rel for rel, _ in pending_over}
    for rel in sorted(PENDING - still):
        print(f"check_file_lengths: done: {rel} is within {LIMIT} lines (or gone); delete it from PENDING")
    print(f"check_file_lengths: {checked} files under {', '.join(DIRS)}, {len(over)} over {LIMIT} lines, "
          f"{len(pending_over)} pending")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
