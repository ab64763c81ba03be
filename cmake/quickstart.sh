#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build in Release for this machine (the `native`
# preset: -march=native, examples only) and run the main job, the reference study's RC tie
# (100 blocks, one 8 mm bar, pulled to past yield). Results go to
# results/rc_tie/: curve.csv, bare_bar.csv, summary.json, VTK snapshots (tie.pvd) and curve.png.
# Extra arguments are passed to rc_tie (see build/native/examples/rc_tie --help). The portable
# `release` preset (what the tests and the README's tables use) gives the same figures to rounding.
set -euo pipefail
cd "$(dirname "$0")/.."
bash cmake/install-deps.sh
cmake --preset native >/dev/null
cmake --build --preset native --target rc_tie
./build/native/examples/rc_tie --out results/rc_tie "$@"
