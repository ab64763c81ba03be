// The program tessera_python_tension_cpp: python/tension_reference.hpp's run (the script
// examples/python/direct_tension.py in C++), writing curve.csv in the working folder and, on
// stdout, the CPU time of the scene and the run (run_cpu_s), as the script prints it.
//
//     tessera_python_tension_cpp [--threads N]
#include "tension_reference.hpp"

#include <tessera/io/csv.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

int main(int argc, char** argv) {
  const int threads = argc == 3 && std::strcmp(argv[1], "--threads") == 0 ? std::atoi(argv[2]) : 1;
  const std::clock_t cpu_start = std::clock();
  const auto curve = tessera::python_reference::tension_curve(threads);
  std::printf("run_cpu_s %.3f\n", static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
  tessera::io::write_csv("curve.csv",
                         {"displacement_m", "stress_Pa", "stress_top_Pa", "stress_bottom_Pa", "unbalanced_ratio"}, curve);
  return 0;
}
