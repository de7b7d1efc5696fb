// core::process_cpu_seconds counts the processor time of every thread, not time spent waiting.
#include "proprio/core/cpu_clock.hpp"

#include <gtest/gtest.h>
#include <time.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace proprio::core {
namespace {

// The calling thread's own processor time, s.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Spins until the calling thread has used `cpu` seconds of processor time (not wall time: on a
// loaded machine a wall-time spin may get only a sliver of a core, and a test of how much was
// counted would fail); returns a value so that the loop is not optimised away.
double spin(double cpu) {
  const double end = thread_cpu_seconds() + cpu;
  double x = 0;
  while (thread_cpu_seconds() < end) {
    for (int i = 0; i < 1000; ++i) x += std::sqrt(x + 1.0);
  }
  return x;
}

TEST(CpuClock, CountsWorkNotSleep) {
  const double c0 = process_cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const double slept = process_cpu_seconds() - c0;
  EXPECT_GE(slept, 0.0);
  EXPECT_LT(slept, 0.1);  // asleep: (almost) no processor time
  const double c1 = process_cpu_seconds();
  EXPECT_GT(spin(0.1), 0.0);
  const double worked = process_cpu_seconds() - c1;
  // The thread's 0.1 s of processor time, and not much more (one thread).
  EXPECT_GE(worked, 0.099);
  EXPECT_LT(worked, 1.0);
}

TEST(CpuClock, CountsEveryThread) {
  // Two threads that each use 0.1 s of processor time: the process clock counts both (so more
  // than one thread's), while the caller only waits.
  const double c0 = process_cpu_seconds();
  std::vector<std::thread> threads;
  std::vector<double> sink(2, 0.0);
  for (std::size_t i = 0; i < 2; ++i) threads.emplace_back([&sink, i] { sink[i] = spin(0.1); });
  for (std::thread& t : threads) t.join();
  const double worked = process_cpu_seconds() - c0;
  EXPECT_GT(sink[0] + sink[1], 0.0);
  EXPECT_GE(worked, 0.199);
}

}  // namespace
}  // namespace proprio::core
