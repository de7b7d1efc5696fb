#pragma once
// The few collective operations that data-parallel learning needs (online LDA, k-means
// vocabularies over MPI, issue 23), behind one interface so that the learning code calls them
// without knowing whether it runs as one process or as a rank of an MPI job. LocalCommunicator is
// the one-process world (every operation a copy or nothing); the MPI one comes from
// core/mpi_communicator.hpp (library proprio::core_mpi, built with Open MPI when CMake finds it).
//
// Every operation is collective: every rank calls it, in the same order, with the same sizes
// where sizes are stated. No floating-point sum is offered: its order would depend on the MPI
// library, and the learners keep their results bit-identical to one process's by gathering what
// they sum and summing it in a fixed order themselves.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "proprio/core/error.hpp"

namespace proprio::core {

/// Bad input that every rank of the job throws alike (agree() below): the CLI prints it once, on
/// rank 0, and every rank exits 2 after leaving MPI cleanly.
class CollectiveError : public Error {
 public:
  explicit CollectiveError(const std::string& message) : Error(message) {}
};

class Communicator {
 public:
  Communicator() = default;
  Communicator(const Communicator&) = delete;
  Communicator& operator=(const Communicator&) = delete;
  virtual ~Communicator() = default;

  [[nodiscard]] virtual int rank() const = 0;
  [[nodiscard]] virtual int size() const = 0;
  /// "local" or "mpi".
  [[nodiscard]] virtual std::string name() const = 0;

  virtual void barrier() = 0;
  /// Copies `data` of rank `root` into `data` of every rank (the same size everywhere).
  virtual void broadcast(std::span<std::byte> data, int root) = 0;
  /// Element-wise sum, minimum or maximum over the ranks, in place (integers: exact, so the
  /// order of the reduction does not matter).
  virtual void allreduce_sum(std::span<std::int64_t> values) = 0;
  virtual void allreduce_min(std::span<std::int64_t> values) = 0;
  virtual void allreduce_max(std::span<std::int64_t> values) = 0;
  /// Every rank's `mine` (any size), concatenated in rank order into `all`; `sizes[r]` is rank r's
  /// byte count.
  virtual void allgather(std::span<const std::byte> mine, std::vector<std::byte>& all,
                         std::vector<std::size_t>& sizes) = 0;
  /// The same when every rank knows every rank's byte count beforehand: `sizes[r]` is rank r's
  /// (the same on every rank; sizes[rank()] == mine.size()), `all` holds their sum and receives
  /// the concatenation. One collective (MPI_Allgatherv) where allgather needs two (the sizes,
  /// then the bytes), and no allocation. This default runs allgather and copies.
  virtual void allgather_sized(std::span<const std::byte> mine, std::span<std::byte> all,
                               std::span<const std::size_t> sizes);
  /// Point to point (the rank-ordered fold below): blocking send to `to`, receive from `from`.
  virtual void send(std::span<const std::byte> data, int to) = 0;
  virtual void receive(std::span<std::byte> data, int from) = 0;
};

/// The world of one process: rank 0 of 1.
class LocalCommunicator final : public Communicator {
 public:
  [[nodiscard]] int rank() const override { return 0; }
  [[nodiscard]] int size() const override { return 1; }
  [[nodiscard]] std::string name() const override { return "local"; }
  void barrier() override {}
  void broadcast(std::span<std::byte>, int) override {}
  void allreduce_sum(std::span<std::int64_t>) override {}
  void allreduce_min(std::span<std::int64_t>) override {}
  void allreduce_max(std::span<std::int64_t>) override {}
  void allgather(std::span<const std::byte> mine, std::vector<std::byte>& all,
                 std::vector<std::size_t>& sizes) override;
  void allgather_sized(std::span<const std::byte> mine, std::span<std::byte> all,
                       std::span<const std::size_t> sizes) override;
  void send(std::span<const std::byte>, int) override;
  void receive(std::span<std::byte>, int) override;
};

/// The number of processes of the MPI job this process was launched in, from the launcher's
/// environment (Open MPI's OMPI_COMM_WORLD_SIZE, MPICH/PMI's PMI_SIZE, PMIx's PMIX_SIZE...), or 0
/// when it was not launched by an MPI launcher.
int launched_mpi_world_size();

/// Runs `step` on every rank and makes its failure everyone's: when `step` throws proprio::Error
/// on some ranks, every rank throws Error with the message of the lowest failing rank (so that a
/// bad input seen by one rank ends the job on all, with one message, instead of a hang in the
/// next collective). It throws CollectiveError, also with one rank. Other exceptions pass through
/// (a bug: the caller aborts the job).
void agree(Communicator& comm, const std::function<void()>& step);

/// Collective: checks that every rank passed the same `text` (by a 64-bit FNV-1a hash of it,
/// compared by a minimum and a maximum over the ranks) and throws CollectiveError(`message`) on
/// every rank when they differ. For the options of a data-parallel job: a rank given other
/// options would send other messages than the rest expect, a hang or a wrong result.
void require_same_on_every_rank(Communicator& comm, std::string_view text,
                                const std::string& message);

/// Every rank's values concatenated in rank order (a typed allgather); `counts[r]` is rank r's
/// number of elements when `counts` is given.
template <class T>
std::vector<T> allgather_values(Communicator& comm, std::span<const T> mine,
                                std::vector<std::size_t>* counts = nullptr) {
  std::vector<std::byte> all;
  std::vector<std::size_t> sizes;
  comm.allgather(std::as_bytes(mine), all, sizes);
  std::vector<T> out(all.size() / sizeof(T));
  if (!all.empty()) std::memcpy(out.data(), all.data(), all.size());
  if (counts != nullptr) {
    counts->clear();
    for (const auto s : sizes) counts->push_back(s / sizeof(T));
  }
  return out;
}

/// A left fold in rank order: rank 0 runs `fold(acc)` on `acc`, sends it to rank 1, which runs its
/// `fold` on it, and so on; the last rank's `acc` is broadcast to all. With sums in `fold` this is
/// the sum in the order of one process running over every rank's data in turn, bit for bit.
void fold_in_rank_order(Communicator& comm, std::span<double> acc,
                        const std::function<void(std::span<double>)>& fold);

}  // namespace proprio::core
