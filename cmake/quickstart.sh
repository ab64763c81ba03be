#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build in Release and run the main job, the
# reference study's RC tie (100 blocks, one 8 mm bar, pulled to past yield). Results go to
# results/rc_tie/: curve.csv, bare_bar.csv, summary.json, VTK snapshots (tie.pvd) and curve.png.
# Extra arguments are passed to rc_tie (see build/release/examples/rc_tie --help).
set -euo pipefail
cd "$(dirname "$0")/.."
bash cmake/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target rc_tie
./build/release/examples/rc_tie --out results/rc_tie "$@"
