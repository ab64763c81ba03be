#!/usr/bin/env bash
# Installs the Debian 12 packages tessera needs, skipping those already present (python3-vtk9:
# the test that reads every VTK file back with VTK's own readers, as ParaView does).
# Needs root (or sudo) only when something is missing.
# --fuzz also installs clang 14 with libFuzzer and its sanitizer runtimes (cmake/run-fuzzers.sh);
# the main build does not need them.
# Optional packages (Open MPI and METIS, for the distributed step: CMake options TESSERA_MPI and
# TESSERA_METIS; SuiteSparse for the implicit solve's supernodal factorisation, TESSERA_CHOLMOD,
# with OpenBLAS's one-thread build, whose BLAS makes CHOLMOD 7x faster than the reference BLAS on
# the 1 000-block prism; Doxygen for the API reference, CMake option TESSERA_DOCS, the `docs` target
# and cmake/check-docs.py; pybind11, Python's headers, NumPy and pytest for the Python module, CMake
# option TESSERA_PYTHON, docs/python.md) are tried after the required ones; when they cannot be installed the
# script says so and succeeds, and tessera builds without them.
set -euo pipefail
packages=(g++ cmake make libeigen3-dev catch2 libbenchmark-dev gnuplot-nox python3-vtk9)
optional=(libopenmpi-dev openmpi-bin libmetis-dev libsuitesparse-dev libopenblas0-serial doxygen
          pybind11-dev python3-dev python3-numpy python3-pytest)
if [[ "${1:-}" == "--fuzz" ]]; then packages+=(clang-14 libclang-rt-14-dev); fi
is_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${packages[@]}"; do is_installed "$p" || missing+=("$p"); done
missing_optional=()
for p in "${optional[@]}"; do is_installed "$p" || missing_optional+=("$p"); done
sudo_cmd=()
[[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
apt_get() { "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get "$@"; }
updated=0
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}" >&2
  apt_get update -qq
  updated=1
  apt_get install -y -qq --no-install-recommends "${missing[@]}"
fi
if ((${#missing_optional[@]})); then
  echo "install-deps: installing the optional ${missing_optional[*]} (MPI and METIS for the distributed step, SuiteSparse and OpenBLAS for the implicit solve, Doxygen for the API reference, pybind11 and NumPy for the Python module)" >&2
  if ! { ((updated)) || apt_get update -qq; } || ! apt_get install -y -qq --no-install-recommends "${missing_optional[@]}"; then
    echo "install-deps: the optional ${missing_optional[*]} could not be installed; tessera builds without them" >&2
  fi
fi
