#!/usr/bin/env bash
# Installs the Debian 12 packages tessera needs, skipping those already present (python3-vtk9:
# the test that reads every VTK file back with VTK's own readers, as ParaView does).
# Needs root (or sudo) only when something is missing.
# --fuzz also installs clang 14 with libFuzzer and its sanitizer runtimes (cmake/run-fuzzers.sh);
# the main build does not need them.
set -euo pipefail
packages=(g++ cmake make libeigen3-dev catch2 libbenchmark-dev gnuplot-nox python3-vtk9)
if [[ "${1:-}" == "--fuzz" ]]; then packages+=(clang-14 libclang-rt-14-dev); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}" >&2
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
