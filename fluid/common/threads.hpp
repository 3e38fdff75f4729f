#pragma once
#include <algorithm>
#include <limits>

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

// Reductions over n entries by the threads with the same bits for any count: kReductionBlocks fixed
// blocks of ceil(n / kReductionBlocks) entries (the last ones shorter or empty), part(at, m) of each
// block [at, at + m) computed by one thread, the blocks' results combined in block order:
// combine(...combine(combine(part_0, part_1), part_2)..., part_last).
constexpr int kReductionBlocks = 64;

template <class T, class Part, class Combine>
T reduce_by_blocks(long n, Part&& part, Combine&& combine) {
  const long len = (n + kReductionBlocks - 1) / kReductionBlocks;
  T s[kReductionBlocks];
#pragma omp parallel for schedule(static)
  for (int b = 0; b < kReductionBlocks; ++b) {
    const long at = std::min(n, b * len);
    s[b] = part(at, std::min(n, at + len) - at);
  }
  T total = s[0];
  for (int b = 1; b < kReductionBlocks; ++b) total = combine(total, s[b]);
  return total;
}

// sum over the blocks of part(at, m) (m may be 0: part must return 0 then)
template <class Part>
double sum_by_blocks(long n, Part&& part) {
  return reduce_by_blocks<double>(n, part, [](double a, double b) { return a + b; });
}

// max over the non-empty blocks of part(at, m) (-infinity for n = 0); exact: a maximum has no rounding
template <class Part>
double max_by_blocks(long n, Part&& part) {
  return reduce_by_blocks<double>(
      n, [&](long at, long m) { return m > 0 ? part(at, m) : -std::numeric_limits<double>::infinity(); },
      [](double top, double v) { return v > top || v != v ? v : top; });  // a NaN stays (as Eigen's maxCoeff may keep it)
}

}  // namespace sphib
