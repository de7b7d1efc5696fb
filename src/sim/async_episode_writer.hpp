#pragma once
// An EpisodeWriter fed from the simulation thread and run on a thread of its own, so that PNG
// encoding overlaps the physics and the rendering of the next frames (recording speed, issue 3).

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "proprio/episode/episode_writer.hpp"

namespace proprio::sim {

class AsyncEpisodeWriter {
 public:
  /// Takes a constructed writer; frames given to add_frame are written on a worker thread, at
  /// most `queue_frames` waiting (add_frame blocks when the queue is full).
  AsyncEpisodeWriter(episode::EpisodeWriter& writer, int queue_frames = 4);
  AsyncEpisodeWriter(const AsyncEpisodeWriter&) = delete;
  AsyncEpisodeWriter& operator=(const AsyncEpisodeWriter&) = delete;
  /// Stops the worker; frames still queued are dropped (the episode is abandoned).
  ~AsyncEpisodeWriter();

  /// Queues a frame (the images are shared, not copied: the caller must not write into them
  /// afterwards). Rethrows the first error the worker met.
  void add_frame(cv::Mat image, const episode::ArmSample& arm, episode::FrameExtras extras);
  /// Waits until every queued frame is written; rethrows the worker's error. Then the caller
  /// finishes the EpisodeWriter itself.
  void drain();

  /// Seconds the worker spent in EpisodeWriter::add_frame, and the simulation thread waited for
  /// room in the queue.
  [[nodiscard]] double write_seconds() const { return write_seconds_; }
  [[nodiscard]] double wait_seconds() const { return wait_seconds_; }

 private:
  struct Item {
    cv::Mat image;
    episode::ArmSample arm;
    episode::FrameExtras extras;
  };
  void run();
  void rethrow_locked();

  episode::EpisodeWriter& writer_;
  std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Item> queue_;
  bool busy_ = false;
  bool stop_ = false;
  std::exception_ptr error_;
  double write_seconds_ = 0.0;
  double wait_seconds_ = 0.0;
  std::thread worker_;
};

}  // namespace proprio::sim
