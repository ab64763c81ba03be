#pragma once
// The thread count of an example driver: `--threads N` (N > 0) runs N threads for the whole run;
// `--threads 0` (auto, the default) starts on one thread per core that other processes leave idle
// and lets the process-wide thread governor (tessera/core/thread_governor.hpp) move between
// fewer and more threads as the run's step times say, so a run that loses a core to another
// program falls back to fewer threads and climbs back when the core frees. Results do not depend
// on the thread count, only the run time does.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "tessera/core/thread_governor.hpp"

namespace tessera::cli {

namespace detail {
/// Busy and total jiffies of all CPUs from the first line of /proc/stat; false if unreadable.
inline bool read_cpu_jiffies(unsigned long long& busy, unsigned long long& total) {
  std::FILE* f = std::fopen("/proc/stat", "r");
  if (f == nullptr) return false;
  unsigned long long v[8] = {};
  const int n = std::fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5],
                            &v[6], &v[7]);
  std::fclose(f);
  if (n < 4) return false;
  const unsigned long long idle = v[3] + v[4];  // idle + iowait
  busy = v[0] + v[1] + v[2] + v[5] + v[6] + v[7];
  total = busy + idle;
  return true;
}
}  // namespace detail

/// The thread count for `--threads 0` (auto): one thread per core that other processes leave
/// idle, at least 1; 0 (the OpenMP default) when OMP_NUM_THREADS is set or the load cannot be
/// read. The load is what the other processes use NOW: the CPU time /proc/stat counts over 0.2 s
/// while this program waits (the 1-minute load average, the fallback, still remembers a build that
/// has just finished). Why: the solver meets two OpenMP barriers per time step, and a thread that
/// shares its core with another process stalls every barrier (measured on 2 cores with a compile
/// job on one: the RC tie took 151 s on 2 threads against 19 s on 1). Results do not depend on
/// the thread count, only the run time does. Prints a note on stderr when it picks fewer threads
/// than there are cores. choose_threads() then lets the thread governor revise the count as the run goes.
inline int auto_threads(const std::string& program) {
  if (std::getenv("OMP_NUM_THREADS") != nullptr) return 0;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (cores <= 1) return 0;
  double busy_cores = 0;
  const char* how = "CPU use of other processes";
  unsigned long long b0 = 0, t0 = 0, b1 = 0, t1 = 0;
  if (detail::read_cpu_jiffies(b0, t0)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (!detail::read_cpu_jiffies(b1, t1) || t1 <= t0) return 0;
    busy_cores = static_cast<double>(cores) * static_cast<double>(b1 - b0) / static_cast<double>(t1 - t0);
  } else {
    how = "load average";
    if (getloadavg(&busy_cores, 1) != 1) return 0;
  }
  const int idle = std::clamp(cores - static_cast<int>(std::lround(busy_cores)), 1, cores);
  if (idle < cores)
    std::fprintf(stderr, "%s: %s %.2f on %d cores, starting on %d thread%s (--threads N fixes N)\n", program.c_str(), how,
                 busy_cores, cores, idle, idle == 1 ? "" : "s");
  return idle;
}

/// The thread count a driver runs with for its `--threads` value `requested` (>= 0): N > 0 is
/// set and kept for the whole run; 0 (auto) starts on auto_threads() and, unless OMP_NUM_THREADS
/// is set or the load cannot be read (then 0: the OpenMP default), starts the thread governor
/// between 1 and the machine's cores. Throws invalid_input for requested < 0.
inline int choose_threads(const std::string& program, int requested) {
  require(requested >= 0, program, ": --threads ", requested, " must be >= 0");
  if (requested > 0) {
    set_threads(requested);
    return requested;
  }
  const int threads = auto_threads(program);
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (threads > 0 && cores > 1) start_thread_governor(threads, std::max(threads, cores));
  return threads;
}

}  // namespace tessera::cli
