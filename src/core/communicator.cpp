#include "proprio/core/communicator.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "proprio/core/checkpoint.hpp"
#include "proprio/core/error.hpp"

namespace proprio::core {

void LocalCommunicator::allgather(std::span<const std::byte> mine, std::vector<std::byte>& all,
                                  std::vector<std::size_t>& sizes) {
  all.assign(mine.begin(), mine.end());
  sizes.assign(1, mine.size());
}

namespace {

// Throws InternalError unless `sizes` has one entry a rank, this rank's is mine.size() and their
// sum is all.size().
void check_sizes(const Communicator& comm, std::size_t mine, std::size_t all,
                 std::span<const std::size_t> sizes) {
  std::size_t total = 0;
  for (const auto s : sizes) total += s;
  const auto me = static_cast<std::size_t>(comm.rank());
  if (sizes.size() != static_cast<std::size_t>(comm.size()) || sizes[me] != mine || total != all) {
    throw InternalError("allgather_sized: the sizes do not match the buffers");
  }
}

}  // namespace

void Communicator::allgather_sized(std::span<const std::byte> mine, std::span<std::byte> all,
                                   std::span<const std::size_t> sizes) {
  check_sizes(*this, mine.size(), all.size(), sizes);
  std::vector<std::byte> got;
  std::vector<std::size_t> got_sizes;
  allgather(mine, got, got_sizes);
  if (!std::equal(got_sizes.begin(), got_sizes.end(), sizes.begin(), sizes.end())) {
    throw InternalError("allgather_sized: a rank sent another size than announced");
  }
  std::copy(got.begin(), got.end(), all.begin());
}

void LocalCommunicator::allgather_sized(std::span<const std::byte> mine, std::span<std::byte> all,
                                        std::span<const std::size_t> sizes) {
  check_sizes(*this, mine.size(), all.size(), sizes);
  std::copy(mine.begin(), mine.end(), all.begin());
}

void LocalCommunicator::send(std::span<const std::byte>, int) {
  throw InternalError("LocalCommunicator: send in a world of one");
}

void LocalCommunicator::receive(std::span<std::byte>, int) {
  throw InternalError("LocalCommunicator: receive in a world of one");
}

int launched_mpi_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"}) {
    const char* v = std::getenv(name);  // NOLINT(concurrency-mt-unsafe): read once at start-up
    if (v != nullptr && *v != '\0') {
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      if (end != v && n > 0) return static_cast<int>(std::min<long>(n, 1 << 24));
    }
  }
  return 0;
}

void agree(Communicator& comm, const std::function<void()>& step) {
  std::string message;
  bool failed = false;
  try {
    step();
  } catch (const CollectiveError& e) {
    message = e.what();
    failed = true;
  } catch (const Error& e) {
    message = e.what();
    failed = true;
  }
  if (comm.size() == 1) {
    if (failed) throw CollectiveError(message);
    return;
  }
  std::int64_t first[1] = {failed ? comm.rank() : comm.size()};
  comm.allreduce_min(first);
  if (first[0] == comm.size()) return;
  const int root = static_cast<int>(first[0]);
  std::int64_t length[1] = {static_cast<std::int64_t>(message.size())};
  comm.broadcast(std::as_writable_bytes(std::span(length)), root);
  message.resize(static_cast<std::size_t>(length[0]));
  comm.broadcast(std::as_writable_bytes(std::span(message.data(), message.size())), root);
  throw CollectiveError(message);
}

void require_same_on_every_rank(Communicator& comm, std::string_view text,
                                const std::string& message) {
  if (comm.size() == 1) return;
  const std::uint64_t h = fnv1a(text);
  std::int64_t v = 0;
  std::memcpy(&v, &h, sizeof v);
  std::int64_t lo[1] = {v};
  std::int64_t hi[1] = {v};
  comm.allreduce_min(lo);
  comm.allreduce_max(hi);
  if (lo[0] != hi[0]) throw CollectiveError(message);
}

void fold_in_rank_order(Communicator& comm, std::span<double> acc,
                        const std::function<void(std::span<double>)>& fold) {
  const int r = comm.rank();
  const int n = comm.size();
  if (r > 0) comm.receive(std::as_writable_bytes(acc), r - 1);
  fold(acc);
  if (r + 1 < n) comm.send(std::as_bytes(acc), r + 1);
  if (n > 1) comm.broadcast(std::as_writable_bytes(acc), n - 1);
}

}  // namespace proprio::core
