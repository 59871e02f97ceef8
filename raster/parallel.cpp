#include "raster/parallel.h"

#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace pelt::raster {

ScopedFlushToZero::ScopedFlushToZero() : saved_(_mm_getcsr()) {
  // FTZ (bit 15) and DAZ (bit 6): denormals cost ~100x on some cores and would make
  // results depend on which code path touched them.
  _mm_setcsr(saved_ | 0x8040u);
}
ScopedFlushToZero::~ScopedFlushToZero() { _mm_setcsr(saved_); }

namespace {

// The threads of `threads` that can run at once: TBB runs no more than the process may use (its
// default concurrency, which follows the affinity mask), and an arena asked for more prints a
// warning on stderr. Images do not depend on the count, so arenas take what can run.
int runnable_threads(int threads) { return std::min(threads, std::max(1, tbb::info::default_concurrency())); }

}  // namespace

void start_worker_threads(int threads) {
  if (threads <= 1) return;
  // An arena kept for the process holds TBB's workers; a job of `threads` items that each wait
  // (briefly, bounded) for the others makes TBB start them now rather than at first use.
  // More threads than cores get no more workers from TBB; one deadline for the whole job
  // bounds the wait however the items are scheduled.
  const int n = runnable_threads(threads);
  static tbb::task_arena keep(n);
  std::atomic<int> started{0};
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
  keep.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 1), [&](const tbb::blocked_range<int>&) {
      started.fetch_add(1);
      while (started.load() < n && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    });
  });
}

struct ThreadPool::Arena {
  explicit Arena(int n) : arena(n) {}
  tbb::task_arena arena;
};

ThreadPool::ThreadPool(int threads) : threads_(threads < 0 ? 0 : threads) {
  if (threads_ > 0) arena_ = std::make_unique<Arena>(runnable_threads(threads_));
}

ThreadPool::~ThreadPool() = default;

void ThreadPool::parallel_for(size_t count, ItemFn fn) {
  if (count == 0) return;
  if (!arena_ || threads_ == 1) {
    ScopedFlushToZero ftz;
    for (size_t i = 0; i < count; ++i) fn(i, 0);
    return;
  }
  // One task per worker, each claiming the next item from a shared counter: items are taken
  // in order (callers put the heaviest tiles first, so the last to finish are short; TBB's
  // recursive halving would hand the second worker the light half), and a frame creates a
  // handful of tasks instead of two per item.
  std::atomic<size_t> next{0};
  const size_t workers = std::min(count, static_cast<size_t>(threads_));
  arena_->arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, workers, 1),
        [&](const tbb::blocked_range<size_t>&) {
          ScopedFlushToZero ftz;
          const int slot = tbb::this_task_arena::current_thread_index();
          for (size_t i = next.fetch_add(1, std::memory_order_relaxed); i < count;
               i = next.fetch_add(1, std::memory_order_relaxed))
            fn(i, slot);
        },
        tbb::simple_partitioner());
  });
}

}  // namespace pelt::raster
