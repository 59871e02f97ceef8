// The one threading wrapper: a parallel_for over independent items (tiles, front-end
// chunks) on a oneTBB arena of a fixed size. Results never depend on the thread count:
// callers write to per-item outputs and merge in item order.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <type_traits>
#include <utility>

namespace pelt::raster {

// A non-owning reference to a callable fn(item, slot): unlike std::function it never
// allocates (the renderer's lambdas capture more than std::function stores inline, and it
// calls parallel_for three times a frame). Valid while the referenced callable lives.
class ItemFn {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, ItemFn>>>
  ItemFn(F&& f)  // NOLINT: implicit, so callers pass lambdas directly
      : obj_(const_cast<void*>(static_cast<const void*>(&f))),
        call_([](void* o, size_t item, int slot) { (*static_cast<std::remove_reference_t<F>*>(o))(item, slot); }) {}
  void operator()(size_t item, int slot) const { call_(obj_, item, slot); }

 private:
  void* obj_;
  void (*call_)(void*, size_t, int);
};

// Calls fn(i) once for every i in [0, count), in any order and possibly on several threads
// at once: how set-up passes outside the renderer (texture builds) borrow its threads
// (Renderer::parallel_for adapts). Callers split their work into items that each write only
// their own outputs, so the result is the same with or without one. (shading::ParallelFor is
// the same type, declared there because shading does not include the rasterizer.)
using ParallelFor = std::function<void(size_t count, const std::function<void(size_t)>& fn)>;

// fn(i) for every i in [0, count): as the items of `parallel` when there is one and more than
// one item, else in order on this thread.
inline void for_each_item(const ParallelFor& parallel, size_t count, const std::function<void(size_t)>& fn) {
  if (parallel && count > 1) {
    parallel(count, fn);
    return;
  }
  for (size_t i = 0; i < count; ++i) fn(i);
}

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
  void parallel_for(size_t count, ItemFn fn);

 private:
  int threads_;
  struct Arena;
  std::unique_ptr<Arena> arena_;
};

// Starts the process's worker threads for pools of `threads` now, and keeps them until exit
// (the first call's width holds; call once). Why: glibc creates a thread only outside another
// thread's dlopen (its TLS lock), and `pelt render` loads OpenImageIO's module on a thread of
// its own while the scene is set up; a pool whose workers were first needed during that load
// stalled until it ended (200-375 ms of a one-frame render's 0.4 s). Call before starting
// such a load.
void start_worker_threads(int threads);

// Sets FTZ/DAZ on the calling thread for its lifetime in scope and restores it after.
class ScopedFlushToZero {
 public:
  ScopedFlushToZero();
  ~ScopedFlushToZero();

 private:
  unsigned saved_;
};

}  // namespace pelt::raster
