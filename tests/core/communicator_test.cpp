// core::Communicator of one process, agree() and the rank-ordered fold; the launcher's
// environment. The MPI world itself is tested through the CLI under mpirun (tests/app/mpi_*).
#include "proprio/core/communicator.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <span>
#include <vector>

#include "proprio/core/mpi_communicator.hpp"

namespace proprio::core {
namespace {

TEST(Communicator, LocalWorldIsRankZeroOfOne) {
  LocalCommunicator c;
  EXPECT_EQ(c.rank(), 0);
  EXPECT_EQ(c.size(), 1);
  std::vector<std::int64_t> v{3, -4};
  c.allreduce_sum(v);
  c.allreduce_min(v);
  EXPECT_EQ(v, (std::vector<std::int64_t>{3, -4}));
  const std::vector<int> mine{1, 2, 3};
  std::vector<std::size_t> counts;
  EXPECT_EQ(allgather_values<int>(c, mine, &counts), mine);
  EXPECT_EQ(counts, std::vector<std::size_t>{3});
}

// The allgather of sizes every rank knows: the bytes land in the caller's buffer; sizes that do
// not match the buffers are a broken invariant.
TEST(Communicator, AllgatherOfKnownSizesFillsTheGivenBufferAndChecksTheSizes) {
  LocalCommunicator c;
  const std::vector<int> mine{4, 5, 6};
  std::vector<int> all(3, 0);
  const std::vector<std::size_t> sizes{3 * sizeof(int)};
  c.allgather_sized(std::as_bytes(std::span<const int>(mine)),
                    std::as_writable_bytes(std::span<int>(all)), sizes);
  EXPECT_EQ(all, mine);
  std::vector<int> longer(4, 0);
  EXPECT_THROW(c.allgather_sized(std::as_bytes(std::span<const int>(mine)),
                                 std::as_writable_bytes(std::span<int>(longer)), sizes),
               InternalError);
  const std::vector<std::size_t> two{12, 0};
  EXPECT_THROW(c.allgather_sized(std::as_bytes(std::span<const int>(mine)),
                                 std::as_writable_bytes(std::span<int>(all)), two),
               InternalError);
}

TEST(Communicator, AgreeTurnsBadInputIntoACollectiveError) {
  LocalCommunicator c;
  EXPECT_NO_THROW(agree(c, [] {}));
  try {
    agree(c, [] { throw Error("corpus.txt:3: bad"); });
    FAIL() << "no throw";
  } catch (const CollectiveError& e) {
    EXPECT_STREQ(e.what(), "corpus.txt:3: bad");
  }
  // A bug is not bad input: it passes through as it is.
  EXPECT_THROW(agree(c, [] { throw InternalError("bug"); }), InternalError);
}

TEST(Communicator, FoldInRankOrderOfOneRankIsTheFold) {
  LocalCommunicator c;
  std::vector<double> acc{1.0, 2.0};
  fold_in_rank_order(c, acc, [](std::span<double> a) {
    a[0] += 0.5;
    a[1] *= 3.0;
  });
  EXPECT_EQ(acc, (std::vector<double>{1.5, 6.0}));
}

TEST(Communicator, LaunchedWorldSizeComesFromTheLauncher) {
  // ctest does not run the unit tests under mpirun.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr) GTEST_SKIP() << "run under mpirun";
  EXPECT_EQ(launched_mpi_world_size(), 0);
  ::setenv("PMI_SIZE", "4", 1);
  EXPECT_EQ(launched_mpi_world_size(), 4);
  ::setenv("PMI_SIZE", "junk", 1);
  EXPECT_EQ(launched_mpi_world_size(), 0);
  ::unsetenv("PMI_SIZE");
  // Not launched by mpirun: the local world, with or without MPI.
  const auto world = world_communicator();
  EXPECT_EQ(world->size(), 1);
  EXPECT_EQ(world->name(), "local");
}

}  // namespace
}  // namespace proprio::core
