#!/usr/bin/env bash
# Compile-time benchmark (issue #40, #64): compiles the README's consumer program
# (tests/consumer/main.cpp, <tessera/tessera.hpp>, a deformable-block solver with face contacts)
# and a small rigid-block scene (benchmarks/compile_time/rigid_scene.cpp, per-role headers,
# detected dry joints), once with the solver compiled in the scene and once taking it from
# tessera::instances (-DTESSERA_USE_INSTANCES: extern templates, compile only), the README's
# arch (tests/consumer/arch.cpp, which includes tessera/instances.hpp), and the guide's
# deformable scene (benchmarks/compile_time/prism_scene.cpp: the consumer program with per-role
# headers and tessera::instances::prism_solver), and prints
#
#   compile_time <name> <seconds> s (user+sys) <megabytes> MB (peak)
#
# per program (those that link tessera::instances compiled with its TESSERA_SEPARATE_COMPILATION,
# so the library's larger ordinary functions are declared only: core/separate_compilation.hpp):
# the compiler's CPU time (user + sys of /usr/bin/time, or of bash's `times` where
# /usr/bin/time is missing), not wall time, because the machines that run it are shared with
# other compiles, and its peak resident memory (/usr/bin/time's %M; "? MB" without it); with
# REPEAT=n (default 1) each is compiled n times and the medians printed.
# A figure, not a test: it fails only when a program does not compile, never on its time.
# Usage: benchmarks/compile_time.sh            (from anywhere; CXX, CXXFLAGS, REPEAT, OUT_DIR)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cxx="${CXX:-g++}"
# The flags of the issue's criterion (<= 8 s and 600 MB at -O2); CXXFLAGS='-O3 -DNDEBUG' for a Release build's.
read -r -a flags <<< "${CXXFLAGS:--O2}"
repeat="${REPEAT:-1}"
out_dir="${OUT_DIR:-$(mktemp -d)}"
mkdir -p "$out_dir"
eigen="$(pkg-config --cflags-only-I eigen3 2>/dev/null || echo -I/usr/include/eigen3)"
read -r -a eigen_flags <<< "$eigen"
common=(-std=c++20 -fopenmp -I"$root/include" "${eigen_flags[@]}" "${flags[@]}")
echo "compile_time: $cxx ${common[*]} -c, CPU time user+sys and peak memory, median of $repeat"

# cpu_seconds <output.o> <compiler args...>: compiles once, prints "<user+sys seconds> <peak MB>".
cpu_seconds() {
  local obj="$1"; shift
  local t="$out_dir/time.txt"
  if [[ -x /usr/bin/time ]]; then
    /usr/bin/time -f "%U %S %M" -o "$t" "$cxx" "${common[@]}" "$@" -c -o "$obj" || return 1
    awk '{printf "%.1f %.0f\n", $1 + $2, $3 / 1024}' "$t"
  else
    # bash's `times` in a subshell: the children's user and sys time, in NmS.SSSs form.
    ( "$cxx" "${common[@]}" "$@" -c -o "$obj" || exit 1; times ) | tail -1 |
      awk '{u = $1; s = $2; sub(/s$/, "", u); sub(/s$/, "", s); split(u, a, "m"); split(s, b, "m");
            printf "%.1f ?\n", a[1] * 60 + a[2] + b[1] * 60 + b[2]}'
  fi
}
# median: the median of the numbers on stdin, one a line ("?" where there are none).
median() {
  sort -g | awk '$1 != "?" {v[++n] = $1} END {if (n) print v[int((n + 1) / 2)]; else print "?"}'
}
# measure <name> <compiler args...>
measure() {
  local name="$1"; shift
  local seconds=() megabytes=()
  for ((k = 0; k < repeat; ++k)); do
    local s
    if ! s="$(cpu_seconds "$out_dir/$name.o" "$@")"; then
      echo "compile_time: $name does not compile" >&2
      exit 1
    fi
    seconds+=("${s% *}")
    megabytes+=("${s#* }")
  done
  echo "compile_time $name $(printf '%s\n' "${seconds[@]}" | median) s (user+sys) $(printf '%s\n' "${megabytes[@]}" | median) MB (peak)"
}

measure consumer "$root/tests/consumer/main.cpp"
measure rigid_scene "$root/benchmarks/compile_time/rigid_scene.cpp"
# Programs that link tessera::instances are compiled with its PUBLIC TESSERA_SEPARATE_COMPILATION
# (core/separate_compilation.hpp): the larger non-template functions come from the library too.
separate=-DTESSERA_SEPARATE_COMPILATION
measure rigid_scene_instances -DTESSERA_USE_INSTANCES "$separate" "$root/benchmarks/compile_time/rigid_scene.cpp"
# The README's arch (tests/consumer/arch.cpp): per-role headers, its solver from tessera::instances.
measure readme_arch "$separate" "$root/tests/consumer/arch.cpp"
# The guide's deformable scene (benchmarks/compile_time/prism_scene.cpp): per-role headers, its
# solver from tessera::instances.
measure prism_scene_instances "$separate" "$root/benchmarks/compile_time/prism_scene.cpp"
