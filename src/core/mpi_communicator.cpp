// The MPI world (Open MPI), compiled into proprio::core_mpi when CMake finds MPI (PROPRIO_MPI).
// Only the calling thread talks to MPI (MPI_THREAD_FUNNELED): the learners' thread pools compute,
// the main thread communicates between their steps.
#include <mpi.h>

#include <climits>
#include <cstdio>
#include <string>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/mpi_communicator.hpp"

namespace proprio::core {
namespace {

void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  std::string message = "MPI ";
  message += what;
  message += " failed: ";
  message.append(text, static_cast<std::size_t>(length));
  message += " (another rank died or the network failed)";
  throw InternalError(message);
}

int count_of(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(INT_MAX)) {
    throw InternalError("MPI: a message of " + std::to_string(bytes) + " bytes (2 GB at most)");
  }
  return static_cast<int>(bytes);
}

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    int provided = 0;
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "init");
    // Errors come back as codes (then InternalError) rather than ending the process in MPI.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;
  ~MpiCommunicator() override { MPI_Finalize(); }

  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }
  [[nodiscard]] std::string name() const override { return "mpi"; }

  void barrier() override { check(MPI_Barrier(MPI_COMM_WORLD), "barrier"); }
  void broadcast(std::span<std::byte> data, int root) override {
    check(MPI_Bcast(data.data(), count_of(data.size()), MPI_BYTE, root, MPI_COMM_WORLD),
          "broadcast");
  }
  void allreduce_sum(std::span<std::int64_t> v) override { reduce(v, MPI_SUM); }
  void allreduce_min(std::span<std::int64_t> v) override { reduce(v, MPI_MIN); }
  void allreduce_max(std::span<std::int64_t> v) override { reduce(v, MPI_MAX); }

  void allgather(std::span<const std::byte> mine, std::vector<std::byte>& all,
                 std::vector<std::size_t>& sizes) override {
    const auto n = static_cast<std::size_t>(size_);
    std::vector<long long> lengths(n);
    const long long own = static_cast<long long>(mine.size());
    check(MPI_Allgather(&own, 1, MPI_LONG_LONG, lengths.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD),
          "allgather of sizes");
    std::vector<int> counts(n);
    std::vector<int> displs(n);
    std::size_t total = 0;
    sizes.resize(n);
    for (std::size_t r = 0; r < n; ++r) {
      sizes[r] = static_cast<std::size_t>(lengths[r]);
      counts[r] = count_of(sizes[r]);
      displs[r] = count_of(total);
      total += sizes[r];
    }
    count_of(total);
    all.resize(total);
    check(MPI_Allgatherv(mine.data(), count_of(mine.size()), MPI_BYTE, all.data(), counts.data(),
                         displs.data(), MPI_BYTE, MPI_COMM_WORLD),
          "allgather");
  }

  void allgather_sized(std::span<const std::byte> mine, std::span<std::byte> all,
                       std::span<const std::size_t> sizes) override {
    const auto n = static_cast<std::size_t>(size_);
    std::size_t total = 0;
    for (const auto s : sizes) total += s;
    if (sizes.size() != n || sizes[static_cast<std::size_t>(rank_)] != mine.size() ||
        total != all.size()) {
      throw InternalError("allgather_sized: the sizes do not match the buffers");
    }
    counts_.resize(n);
    displs_.resize(n);
    std::size_t at = 0;
    for (std::size_t r = 0; r < n; ++r) {
      counts_[r] = count_of(sizes[r]);
      displs_[r] = count_of(at);
      at += sizes[r];
    }
    check(MPI_Allgatherv(mine.data(), count_of(mine.size()), MPI_BYTE, all.data(), counts_.data(),
                         displs_.data(), MPI_BYTE, MPI_COMM_WORLD),
          "allgather");
  }

  void send(std::span<const std::byte> data, int to) override {
    check(MPI_Send(data.data(), count_of(data.size()), MPI_BYTE, to, 0, MPI_COMM_WORLD), "send");
  }
  void receive(std::span<std::byte> data, int from) override {
    check(MPI_Recv(data.data(), count_of(data.size()), MPI_BYTE, from, 0, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE),
          "receive");
  }

 private:
  void reduce(std::span<std::int64_t> v, MPI_Op op) {
    check(
        MPI_Allreduce(MPI_IN_PLACE, v.data(), count_of(v.size()), MPI_INT64_T, op, MPI_COMM_WORLD),
        "allreduce");
  }

  int rank_ = 0;
  int size_ = 1;
  std::vector<int> counts_;  // allgather_sized's, kept between calls
  std::vector<int> displs_;
};

}  // namespace

bool built_with_mpi() { return true; }

std::unique_ptr<Communicator> world_communicator() {
  if (launched_mpi_world_size() == 0) return std::make_unique<LocalCommunicator>();
  return std::make_unique<MpiCommunicator>();
}

void abort_world(int code) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (initialized != 0 && finalized == 0) MPI_Abort(MPI_COMM_WORLD, code);
}

}  // namespace proprio::core
