#!/usr/bin/env bash
# Quick start, step 1: install what is missing, build in Release and run the main job.
# Results go to results/<example>/ (curve.csv, summary.json, VTK files, plot.png).
set -euo pipefail
cd "$(dirname "$0")/.."
bash cmake/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target tessellate
./build/release/examples/tessellate --out results/tessellate "$@"
