#pragma once
// The one data-parallel loop of proprio: tasks handed out to a few threads (the caller's among
// them), results kept by task index, and reductions combined in a fixed order, so that a result
// never depends on the thread count. It runs on core::ThreadPool (thread_pool.hpp), the one pool
// type: one pool per call here; the LDA engine keeps one across its many short rounds. Standard
// threads only (no OpenCV, no OpenMP), so that every module can use it.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "proprio/core/thread_pool.hpp"

namespace proprio::core {

/// Threads to use for `requested` (0 = the hardware's count), at least 1 and never more than
/// `tasks` (when tasks > 0).
inline int thread_count(int requested, std::size_t tasks) {
  int t = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
  t = std::max(t, 1);
  return static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(t), std::max<std::size_t>(tasks, 1)));
}

/// [begin, end) of chunk `c` of `chunks` equal parts of [0, n): the same split for any thread
/// count, so that per-chunk partial results are the same too.
inline std::pair<std::size_t, std::size_t> chunk_range(std::size_t c, std::size_t chunks,
                                                       std::size_t n) {
  return {c * n / chunks, (c + 1) * n / chunks};
}

/// Calls fn(task, thread) for every task in [0, tasks) on the threads of `pool` (a pool the
/// caller keeps across many short rounds), tasks handed out one at a time in increasing order;
/// `thread` in [0, pool.size()) lets a caller keep one workspace per thread. fn must write only
/// what belongs to its task (or its thread's workspace). If fn throws, the tasks below the
/// failing one still run, the tasks above the lowest failure are skipped, and the exception of
/// the lowest-numbered failing task is rethrown once every thread is done.
template <typename Fn>
void parallel_for(ThreadPool& pool, std::size_t tasks, Fn&& fn) {
  // Tasks are claimed in increasing order, so when task f fails every task below f has been
  // claimed already and runs.
  std::atomic<std::size_t> lowest_failure{tasks};
  std::mutex error_mutex;
  std::exception_ptr error;
  pool.run(tasks, [&](std::size_t t, int thread) {
    if (t > lowest_failure.load(std::memory_order_relaxed)) return;
    try {
      fn(t, thread);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (t < lowest_failure.load(std::memory_order_relaxed)) {
        lowest_failure.store(t, std::memory_order_relaxed);
        error = std::current_exception();
      }
    }
  });
  if (error) std::rethrow_exception(error);
}

/// parallel_for on thread_count(threads, tasks) threads (a pool for this call only).
template <typename Fn>
void parallel_for(std::size_t tasks, int threads, Fn&& fn) {
  ThreadPool pool(thread_count(threads, tasks));
  parallel_for(pool, tasks, std::forward<Fn>(fn));
}

/// partial(c) for every chunk c in [0, chunks) in parallel, then combine(accumulator, partial)
/// in chunk order 0, 1, ..., so that the (floating-point) result is the same for any thread
/// count. Returns the accumulator, which starts as `init`.
template <typename T, typename Partial, typename Combine>
T parallel_reduce(std::size_t chunks, int threads, T init, Partial&& partial, Combine&& combine) {
  std::vector<T> parts(chunks, init);
  parallel_for(chunks, threads, [&](std::size_t c, int) { parts[c] = partial(c); });
  T acc = std::move(init);
  for (T& p : parts) combine(acc, std::move(p));
  return acc;
}

}  // namespace proprio::core
