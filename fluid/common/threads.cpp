#include "fluid/common/threads.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace sphib {

int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

int default_thread_count() {
#ifdef _OPENMP
  if (std::getenv("OMP_NUM_THREADS")) return thread_count();
  const int cores = omp_get_num_procs();
  int others = 0;
  std::ifstream f("/proc/loadavg");  // "0.61 1.64 1.89 2/345 6789": the fourth field is running/total
  std::string a, b, c, running;
  if (f >> a >> b >> c >> running) {
    try {
      others = std::stoi(running.substr(0, running.find('/'))) - 1;
    } catch (const std::exception&) {
      others = 0;
    }
  }
  return std::clamp(cores - std::max(others, 0), 1, cores);
#else
  return 1;
#endif
}

ThreadCount::ThreadCount(int n) : saved_(thread_count()) {
#ifdef _OPENMP
  if (n > 0) omp_set_num_threads(n);
#else
  (void)n;
#endif
}

ThreadCount::~ThreadCount() {
#ifdef _OPENMP
  omp_set_num_threads(saved_);
#endif
}

}  // namespace sphib
