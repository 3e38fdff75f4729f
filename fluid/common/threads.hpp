#pragma once
// How many threads the step's passes and solves share (OpenMP: the products and fused passes by row
// blocks, fluid/algebra/stencil_kernels.hpp; the lattice solvers by columns, row blocks and wavenumbers,
// fluid/algebra/fft_poisson.hpp). Every row, column and wavenumber is computed by one thread in its own
// order, so results do not depend on the count. Without a count set: OMP_NUM_THREADS, else the
// machine's cores.
namespace sphib {

// The threads a parallel pass started now would use (1 without OpenMP).
int thread_count();

// The count a run takes when none is given: OMP_NUM_THREADS when set, else the machine's cores less
// the tasks running now besides this process (/proc/loadavg's fourth field), at least 1. A thread
// that waits for a busy core holds up the others at every pass (two threads on one free core ran
// 5-100x slower than one), so a busy machine gets fewer threads; the results are the same.
int default_thread_count();

// Sets the count for the passes started on this thread while it lives (n >= 1; 0 leaves it as it
// is), then restores the count before it.
class ThreadCount {
 public:
  explicit ThreadCount(int n);
  ~ThreadCount();
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  int saved_;
};

}  // namespace sphib
