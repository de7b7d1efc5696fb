#pragma once
// A data-parallel loop over tasks on a few threads (the caller's included).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace proprio::features::detail {

/// Threads to use for `requested` (0 = the hardware's count), never more than `tasks`.
inline int thread_count(int requested, std::size_t tasks) {
  int t = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
  t = std::max(t, 1);
  return static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(t), std::max<std::size_t>(tasks, 1)));
}

/// Calls fn(task, thread) for every task in [0, tasks), tasks handed out one at a time.
/// fn must not throw.
template <typename Fn>
void parallel_for(std::size_t tasks, int threads, Fn&& fn) {
  threads = thread_count(threads, tasks);
  std::atomic<std::size_t> next{0};
  auto work = [&](int thread) {
    for (std::size_t t = next++; t < tasks; t = next++) fn(t, thread);
  };
  if (threads == 1) {
    work(0);
    return;
  }
  std::vector<std::jthread> pool;
  pool.reserve(static_cast<std::size_t>(threads - 1));
  for (int i = 1; i < threads; ++i) pool.emplace_back(work, i);
  work(0);
}

}  // namespace proprio::features::detail
