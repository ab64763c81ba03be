#!/usr/bin/env bash
# Cost per contact-step of tessera and of YADE's CPM concrete model on the same plain prism in
# direct tension, run one after the other on this machine, one thread each (docs/performance.md).
#   bash benchmarks/side_by_side.sh [BUILD_DIR] [YADE_SPHERE_RADIUS_M]
# BUILD_DIR holds examples/direct_tension (default build/release: the portable build the tests
# use). YADE is optional: Debian's `yade` package; without it only tessera's figure is printed.
# tessera's figure is all-in (zones, gridpoints, contacts, recorders) per sub-contact-step;
# YADE's is all-in per real interaction-step. Results: build/side_by_side/{tessera,yade}.json.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
radius=${2:-0.006}
out=build/side_by_side
mkdir -p "$out"
exe="$build/examples/direct_tension"
[[ -x "$exe" ]] || { echo "side_by_side: no $exe (build the examples first: cmake --workflow --preset test)" >&2; exit 2; }

echo "tessera: 100-block prism, one thread ..." >&2
OMP_NUM_THREADS=1 "$exe" --threads 1 --blocks 100 --out "$out/tessera" > "$out/tessera.log" 2>&1
tessera_ns=$(python3 - "$out/tessera/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{s['runtime_s'] * 1e9 / (s['steps'] * s['subcontacts']):.1f}")
PY
)
echo "tessera: $tessera_ns ns per sub-contact-step (all-in)"

if ! command -v yade > /dev/null; then
  echo "yade: not installed (apt-get install yade); skipped"
  exit 0
fi
echo "yade: CPM prism, sphere radius $radius m, one thread ..." >&2
(cd "$out" && OMP_NUM_THREADS=1 yade -j1 -n -x "$OLDPWD/benchmarks/yade/cpm_prism.py" "$radius" yade.json > yade.log 2>&1 < /dev/null)
yade_ns=$(python3 -c "import json; print(f\"{json.load(open('$out/yade.json'))['ns_per_contact_step']:.1f}\")")
echo "yade:    $yade_ns ns per interaction-step (all-in)"
python3 -c "print(f'ratio yade / tessera: {$yade_ns / $tessera_ns:.2f}')"
