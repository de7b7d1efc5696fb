#include "async_episode_writer.hpp"

#include <cassert>
#include <chrono>

namespace proprio::sim {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

AsyncEpisodeWriter::AsyncEpisodeWriter(episode::EpisodeWriter& writer, int queue_frames)
    : writer_(writer), capacity_(static_cast<std::size_t>(queue_frames)) {
  assert(queue_frames >= 1);
  worker_ = std::thread([this] { run(); });
}

AsyncEpisodeWriter::~AsyncEpisodeWriter() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
    queue_.clear();
  }
  changed_.notify_all();
  worker_.join();
}

void AsyncEpisodeWriter::rethrow_locked() {
  if (error_) {
    // Thrown once: later calls (the destructor's path) see no error again.
    std::exception_ptr e = error_;
    error_ = nullptr;
    stop_ = true;
    std::rethrow_exception(e);
  }
}

void AsyncEpisodeWriter::add_frame(cv::Mat image, const episode::ArmSample& arm,
                                   episode::FrameExtras extras) {
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < capacity_ || error_ || stop_; });
  wait_seconds_ += seconds_since(t0);
  rethrow_locked();
  assert(!stop_);
  queue_.push_back({std::move(image), arm, std::move(extras)});
  lock.unlock();
  changed_.notify_all();
}

void AsyncEpisodeWriter::drain() {
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return (queue_.empty() && !busy_) || error_; });
  wait_seconds_ += seconds_since(t0);
  rethrow_locked();
}

void AsyncEpisodeWriter::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !queue_.empty() || stop_; });
    if (stop_) return;
    Item item = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    changed_.notify_all();
    const auto t0 = std::chrono::steady_clock::now();
    std::exception_ptr error;
    try {
      writer_.add_frame(item.image, item.arm, item.extras);
    } catch (...) {
      error = std::current_exception();
    }
    const double spent = seconds_since(t0);
    lock.lock();
    write_seconds_ += spent;
    busy_ = false;
    if (error) {
      error_ = error;
      queue_.clear();
      changed_.notify_all();
      // Wait for the simulation thread to collect the error and stop us.
      changed_.wait(lock, [&] { return stop_; });
      return;
    }
    changed_.notify_all();
  }
}

}  // namespace proprio::sim
