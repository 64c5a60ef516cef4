// ParallelFor: runs fn(i) for every i in [0, n) on up to `threads` threads
// (the calling thread is one of them), each thread taking the next index
// from a shared counter. Results are deterministic whenever fn(i) writes
// only its own slot i, as the diagnosis' candidate fits and the ANN's
// ensemble members do.
//
// Thread-safety: fn is called concurrently from several threads; it must be
// safe to call so. ParallelFor returns after every call has returned.
#ifndef ROLLWEAR_CORE_BASE_PARALLEL_H_
#define ROLLWEAR_CORE_BASE_PARALLEL_H_

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace rollwear {

template <typename Fn>
void ParallelFor(int n, int threads, Fn fn) {
  std::atomic<int> next{0};
  auto worker = [&]() {
    for (int i = next++; i < n; i = next++) fn(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::min(threads, n); ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_BASE_PARALLEL_H_
