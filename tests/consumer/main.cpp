// A separate project that only knows find_package(tessera): checks that the installed
// headers are self-contained and the exported target carries C++20 and Eigen.
#include <tessera/tessera.hpp>
#include <cmath>
#include <cstdio>

int main() {
  const auto box = tessera::geometry::convex_polyhedron::box({0, 0, 0}, {1, 2, 3});
  const double v = box.volume();
  std::printf("installed tessera %s: box volume %.3f\n", TESSERA_VERSION_STRING, v);
  return std::abs(v - 6.0) < 1e-12 ? 0 : 1;
}
