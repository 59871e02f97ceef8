// The one threading wrapper: a parallel_for over independent items (tiles, front-end
// chunks) on a oneTBB arena of a fixed size. Results never depend on the thread count:
// callers write to per-item outputs and merge in item order.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace pelt::raster {

class ThreadPool {
 public:
  // threads >= 1: an arena of that many workers (the calling thread is one of them).
  // threads == 0: items run inline on the calling thread, in order (for debugging).
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return threads_; }
  // Number of distinct worker slots `fn` may see (>= 1).
  int slots() const { return threads_ > 0 ? threads_ : 1; }

  // Calls fn(item, slot) for item in [0, count); slot < slots() identifies the worker so
  // it can use per-worker scratch. Each worker runs with flush-to-zero and
  // denormals-are-zero set, so every thread count computes the same floats.
  void parallel_for(size_t count, const std::function<void(size_t item, int slot)>& fn);

 private:
  int threads_;
  struct Arena;
  std::unique_ptr<Arena> arena_;
};

// Sets FTZ/DAZ on the calling thread for its lifetime in scope and restores it after.
class ScopedFlushToZero {
 public:
  ScopedFlushToZero();
  ~ScopedFlushToZero();

 private:
  unsigned saved_;
};

}  // namespace pelt::raster
