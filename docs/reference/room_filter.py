#!/usr/bin/env python3
"""Doxygen input filter: a public header's declarations join the group of its room.

Doxygen runs it on each header (FILTER_PATTERNS in Doxyfile.in) and reads its output instead of
the file. The header under include/tessera/<room>/ (or the module header include/tessera/<room>.hpp)
is wrapped in \\addtogroup <room> @{ ... @}: its first line, `#pragma once` (which Doxygen has no
use for), becomes the group's opening and the closing goes after the last line, so every line
keeps its number and Doxygen's warnings point at the header's own lines. tessera.hpp and
instances.hpp join core. The groups themselves are defined in groups.dox.

In the documentation comments, the period of an abbreviation (e.g., i.e., eq., et al.) is escaped,
so that Doxygen's brief description (the first sentence) does not end there.

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


ABBREVIATIONS = ("e.g. ", "i.e. ", "eq. ", "Eq. ", "eqs. ", "cf. ", "vs. ", "al. ", "resp. ", "approx. ")
COMMENT_STARTS = ("///", "//!", "/**", "/*!")


def escape_abbreviations(line):
    """The line with `abbr. ` turned into `abbr.\\ ` in its documentation comment part."""
    starts = [i for i in (line.find(c) for c in COMMENT_STARTS) if i >= 0]
    if not starts:
        return line
    k = min(starts)
    doc = line[k:]
    for a in ABBREVIATIONS:
        doc = doc.replace(a, a[:-1] + "\\ ")
    return line[:k] + doc


def main():
    path = sys.argv[1]
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    lines = [escape_abbreviations(line) for line in lines]
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
