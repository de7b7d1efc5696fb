#include "proprio/core/stderr_capture.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace proprio::core {
namespace {

TEST(StderrCapture, WhatALibraryPrintsIsCapturedAndStderrRestored) {
  ::testing::internal::CaptureStderr();  // what reaches the real descriptor 2
  {
    const StderrCapture outer("test");
    std::fprintf(stderr, "libjpeg: Premature end\n");
    {
      const StderrCapture inner("test");  // nested: one shared redirection
      (void)::write(STDERR_FILENO, "raw write\n", 10);
    }
    EXPECT_EQ(StderrCapture::pending(), "libjpeg: Premature end\nraw write\n");
  }
  EXPECT_EQ(StderrCapture::pending(), "");  // closed: nothing held
  std::fprintf(stderr, "after\n");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "after\n");
}

TEST(StderrCapture, OverlappingCapturesFromThreadsNeverLeak) {
  ::testing::internal::CaptureStderr();
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([] {
      for (int i = 0; i < 200; ++i) {
        const StderrCapture c("thread");
        std::fprintf(stderr, "codec warning\n");
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace proprio::core
