#!/usr/bin/env python3
"""Every public symbol of tessera's headers is documented: Doxygen's undocumented-symbol warnings.

Runs Doxygen (docs/reference/Doxyfile.in, the configuration of the `docs` target) with
WARN_IF_UNDOCUMENTED = YES and no HTML output, keeps the warnings about undocumented symbols in
the public headers (include/tessera, outside detail/ folders; the detail namespaces are excluded
by the configuration itself), prints them with their count per header and fails when there is
one. Nothing is allow-listed: a new public class, function, member or enumerator comes with its
/// comment (what it is, its units and sign, what it refuses).

Exit status: 0 when every public symbol is documented, 1 when one is not, 2 when Doxygen is
absent or fails (.ci/extended skips the check with a message where it is absent).

Usage: check-docs.py [--doxygen PATH] [--keep DIR]
"""
import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WARNING = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+): warning: (?P<text>.*)$")
UNDOCUMENTED = ("is not documented", "not documented")


def configure(template, output_dir):
    """The configuration with its @...@ values filled in, as configure_file does in CMake."""
    with open(template, encoding="utf-8") as f:
        text = f.read()
    values = {
        "TESSERA_SOURCE_DIR": ROOT,
        "TESSERA_DOCS_OUTPUT": output_dir,
        "TESSERA_DOCS_WARN_UNDOCUMENTED": "YES",
        "TESSERA_DOCS_HAVE_DOT": "NO",
        "PROJECT_VERSION": "",
        "Python3_EXECUTABLE": sys.executable,
    }
    for key, value in values.items():
        text = text.replace("@%s@" % key, value)
    # Only the warnings are wanted: no HTML to write.
    return text + "\nGENERATE_HTML = NO\n"


def public_header(path):
    """The path relative to ROOT when it is a public header (include/tessera, not detail/), else None."""
    rel = os.path.relpath(os.path.abspath(path), ROOT).replace(os.sep, "/")
    if not rel.startswith("include/tessera/") or "/detail/" in rel or not rel.endswith(".hpp"):
        return None
    return rel


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--doxygen", default=shutil.which("doxygen"), help="the doxygen executable")
    parser.add_argument("--keep", help="write Doxygen's configuration and full log into DIR")
    args = parser.parse_args()
    if not args.doxygen:
        print("check-docs: doxygen not found (Debian: apt-get install doxygen)", file=sys.stderr)
        return 2
    work = args.keep or tempfile.mkdtemp(prefix="tessera-docs-")
    os.makedirs(work, exist_ok=True)
    config = os.path.join(work, "Doxyfile")
    with open(config, "w", encoding="utf-8") as f:
        f.write(configure(os.path.join(ROOT, "docs", "reference", "Doxyfile.in"), work))
    run = subprocess.run([args.doxygen, config], cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(run.stdout + run.stderr)
        print("check-docs: doxygen failed with status %d" % run.returncode, file=sys.stderr)
        return 2
    with open(os.path.join(work, "warnings.log"), encoding="utf-8", errors="replace") as f:
        log = f.read().splitlines()
    found = []
    for line in log:
        m = WARNING.match(line)
        if not m or not any(u in m.group("text") for u in UNDOCUMENTED):
            continue
        rel = public_header(m.group("file"))
        if rel is not None:
            found.append((rel, int(m.group("line")), m.group("text")))
    found = sorted(set(found))
    per_header = collections.Counter(rel for rel, _, _ in found)
    for rel, line, text in found:
        print("%s:%d: %s" % (rel, line, text))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    if found:
        print("\nundocumented public symbols per header:")
        for rel, n in sorted(per_header.items(), key=lambda kv: (-kv[1], kv[0])):
            print("%5d  %s" % (n, rel))
        print("check-docs: %d undocumented public symbols in %d headers" % (len(found), len(per_header)),
              file=sys.stderr)
        return 1
    print("check-docs: every public symbol in include/tessera is documented")
    return 0


if __name__ == "__main__":
    sys.exit(main())
