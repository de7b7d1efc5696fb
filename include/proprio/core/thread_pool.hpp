#pragma once
// The one pool of worker threads in proprio: core::parallel_for runs on it (one pool per call),
// and a caller that runs many short parallel rounds keeps one alive across them. The LDA engine
// does (topics/engine.hpp): an online LDA run makes thousands of rounds a second (an E-step over
// a mini-batch, the sufficient statistics, the lambda update), each a few hundred microseconds,
// where starting and joining threads for every round would cost as much as the work. Standard
// threads only (no OpenCV, no OpenMP), so that every module can use it.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace proprio::core {

class ThreadPool {
 public:
  /// A pool of `threads` (>= 1) threads, the caller's included.
  explicit ThreadPool(int threads);
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  ~ThreadPool();

  [[nodiscard]] int size() const { return static_cast<int>(workers_.size()) + 1; }

  /// Calls fn(task, thread) for every task in [0, n), handing tasks out one at a time in
  /// increasing order to whichever thread is free (thread in [0, size())); returns when all are
  /// done. fn must not throw (parallel_for catches for its callers). A worker that wakes after
  /// the caller has taken the last task sits the round out, so on a busy machine the caller never
  /// waits for a thread that is still waiting to be scheduled.
  void run(std::size_t n, const std::function<void(std::size_t, int)>& fn);

 private:
  void work(int thread);
  void drain(int thread);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  const std::function<void(std::size_t, int)>* fn_ = nullptr;
  std::size_t tasks_ = 0;
  std::atomic<std::size_t> next_{0};
  std::size_t generation_ = 0;
  bool open_ = false;  ///< workers may still join the current round
  int active_ = 0;     ///< workers in the current round
  bool stop_ = false;
};

}  // namespace proprio::core
