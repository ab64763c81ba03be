#!/usr/bin/env python3
"""Doxygen input filter: a public header's declarations join the group of its room.

Doxygen runs it on each header (FILTER_PATTERNS in Doxyfile.in) and reads its output instead of
the file. The header under include/tessera/<room>/ (or the module header include/tessera/<room>.hpp)
is wrapped in \\addtogroup <room> @{ ... @}: its first line, `#pragma once` (which Doxygen has no
use for), becomes the group's opening and the closing goes after the last line, so every line
keeps its number and Doxygen's warnings point at the header's own lines. tessera.hpp and
instances.hpp join core. The groups themselves are defined in groups.dox.

Usage: room_filter.py HEADER
"""
import os
import sys

ROOMS = {"analysis", "blocks", "contact", "core", "distributed", "geometry", "integrator", "io",
         "law", "presets", "reinforcement", "solver"}


def room_of(path):
    """The room of a header, from the folder after include/tessera/, or None outside it."""
    parts = os.path.normpath(os.path.abspath(path)).split(os.sep)
    for i in range(len(parts) - 2, -1, -1):
        if parts[i] == "tessera" and i > 0 and parts[i - 1] == "include":
            rest = parts[i + 1:]
            name = rest[0][:-4] if len(rest) == 1 and rest[0].endswith(".hpp") else rest[0]
            return name if name in ROOMS else "core"
    return None


def main():
    path = sys.argv[1]
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    room = room_of(path)
    if room is not None and lines and lines[0].strip() == "#pragma once":
        lines[0] = "/** \\addtogroup %s */ /** @{ */" % room
        if lines[-1] == "":
            lines[-1] = "/** @} */"
            lines.append("")
        else:
            lines.append("/** @} */")
    sys.stdout.write("\n".join(lines))


if __name__ == "__main__":
    main()
