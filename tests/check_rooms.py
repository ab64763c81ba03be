#!/usr/bin/env python3
"""The house's rooms include only rooms below them (docs/architecture.md, "The map").

Reads every header under include/tessera/<room>/ and fails, naming the file and the include,
when a room includes a room that is not below it in ORDER (the umbrella headers
include/tessera/*.hpp are exempt: they gather rooms). Usage: check_rooms.py INCLUDE_DIR
"""
import os
import re
import sys

# Lowest first. A room may include itself and any room to its left.
ORDER = ["core", "geometry", "law", "integrator", "blocks", "contact", "reinforcement", "io", "solver",
         "distributed", "analysis", "presets", "instances"]
RANK = {room: k for k, room in enumerate(ORDER)}


def main(root):
    base = os.path.join(root, "tessera")
    bad, edges = [], set()
    for dirpath, _, files in os.walk(base):
        rel = os.path.relpath(dirpath, base)
        if rel == ".":
            continue
        room = rel.split(os.sep)[0]
        if room not in RANK:
            bad.append(f"{rel}: room '{room}' is not in the order {ORDER}")
            continue
        for name in files:
            if not name.endswith(".hpp"):
                continue
            path = os.path.join(dirpath, name)
            with open(path, encoding="utf-8") as f:
                for line in f:
                    m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
                    if not m:
                        continue
                    target = os.path.normpath(os.path.join(dirpath, m.group(1)))
                    trel = os.path.relpath(target, base)
                    troom = trel.split(os.sep)[0]
                    if troom == room or troom not in RANK:
                        continue
                    edges.add((room, troom))
                    if RANK[troom] > RANK[room]:
                        bad.append(f"{os.path.relpath(path, root)} includes {m.group(1)}: room '{room}' "
                                   f"includes '{troom}', which is above it")
    for b in bad:
        print("check_rooms:", b)
    print(f"check_rooms: {len(edges)} room-to-room edges, {len(bad)} against the order {' < '.join(ORDER)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "include"))
