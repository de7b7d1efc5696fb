#pragma once
// The one data-parallel loop of proprio: tasks handed out to a few threads (the caller's among
// them), results kept by task index, and reductions combined in a fixed order, so that a result
// never depends on the thread count. Standard threads only (no OpenCV, no OpenMP), so that every
// module can use it. The LDA engine keeps its own persistent pool (topics/thread_pool.hpp): it
// runs thousands of tiny rounds per second, where starting threads per call would cost more than
// the work.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

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

/// Calls fn(task, thread) for every task in [0, tasks) on thread_count(threads, tasks) threads,
/// tasks handed out one at a time in increasing order; `thread` in [0, threads) lets a caller
/// keep one workspace per thread. fn must write only what belongs to its task (or its thread's
/// workspace). If fn throws, no further task is claimed, the claimed ones finish, the threads
/// are joined, and the exception of the lowest-numbered failing task is rethrown.
template <typename Fn>
void parallel_for(std::size_t tasks, int threads, Fn&& fn) {
  threads = thread_count(threads, tasks);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex error_mutex;
  std::exception_ptr error;
  std::size_t error_task = tasks;
  auto work = [&](int thread) {
    // A task once claimed always runs: the failure of a later task cannot hide an earlier one.
    while (!failed.load(std::memory_order_relaxed)) {
      const std::size_t t = next++;
      if (t >= tasks) break;
      try {
        fn(t, thread);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (t < error_task) {
          error_task = t;
          error = std::current_exception();
        }
        failed = true;
      }
    }
  };
  if (threads == 1) {
    work(0);
  } else {
    std::vector<std::jthread> pool;
    pool.reserve(static_cast<std::size_t>(threads - 1));
    for (int i = 1; i < threads; ++i) pool.emplace_back(work, i);
    work(0);
  }  // the jthreads join here
  if (error) std::rethrow_exception(error);
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
