// core::process_cpu_seconds counts the processor time of every thread, not time spent waiting.
#include "proprio/core/cpu_clock.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace proprio::core {
namespace {

// Spins for `wall` of wall-clock time; returns a value so that the loop is not optimised away.
double spin(std::chrono::milliseconds wall) {
  const auto end = std::chrono::steady_clock::now() + wall;
  double x = 0;
  while (std::chrono::steady_clock::now() < end) x += std::sqrt(x + 1.0);
  return x;
}

TEST(CpuClock, CountsWorkNotSleep) {
  const double c0 = process_cpu_seconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const double slept = process_cpu_seconds() - c0;
  EXPECT_GE(slept, 0.0);
  EXPECT_LT(slept, 0.1);  // asleep: (almost) no processor time
  const double c1 = process_cpu_seconds();
  EXPECT_GT(spin(std::chrono::milliseconds(200)), 0.0);
  const double worked = process_cpu_seconds() - c1;
  // At most the wall time (one thread), at least a share of it on a loaded machine.
  EXPECT_GT(worked, 0.02);
  EXPECT_LT(worked, 1.0);
}

TEST(CpuClock, CountsEveryThread) {
  // Two threads that each spin for the same wall time: the process clock counts both (so more
  // than one thread's share), while the caller only waits.
  const double c0 = process_cpu_seconds();
  std::vector<std::thread> threads;
  std::vector<double> sink(2, 0.0);
  for (std::size_t i = 0; i < 2; ++i)
    threads.emplace_back([&sink, i] { sink[i] = spin(std::chrono::milliseconds(150)); });
  for (std::thread& t : threads) t.join();
  const double worked = process_cpu_seconds() - c0;
  EXPECT_GT(sink[0] + sink[1], 0.0);
  EXPECT_GT(worked, 0.02);
}

}  // namespace
}  // namespace proprio::core
