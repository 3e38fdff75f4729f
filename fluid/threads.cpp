#include "fluid/threads.hpp"

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
