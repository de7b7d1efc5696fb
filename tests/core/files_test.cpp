#include "proprio/core/files.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <random>
#include <set>
#include <string>
#include <string_view>
#include <thread>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace {
namespace fs = std::filesystem;

class FilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("proprio_files_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(FilesTest, AtomicWriteRoundTripsAndLeavesNoTemporary) {
  const fs::path p = dir_ / "sub" / "a.txt";
  write_file_atomic(p, std::string("hello\0world", 11));
  EXPECT_EQ(read_file(p), std::string("hello\0world", 11));
  write_file_atomic(p, "second");
  EXPECT_EQ(read_file(p), "second");
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_ / "sub")) ++n;
  EXPECT_EQ(n, 1);
}

TEST_F(FilesTest, ReadMissingNamesTheFile) {
  try {
    read_file(dir_ / "nope.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "nope.txt").string() + ": no such file");
  }
  EXPECT_THROW(read_file(dir_), Error);
}

TEST_F(FilesTest, StagedDirectoryAppearsOnlyOnCommit) {
  const fs::path out = dir_ / "episode";
  {
    StagedDirectory staged(out);
    write_file_atomic(staged.staging_path() / "x.txt", "1");
    EXPECT_FALSE(fs::exists(out));
  }  // destroyed without commit: an interrupted writer
  EXPECT_FALSE(fs::exists(out));
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
  EXPECT_EQ(n, 0) << "the staging directory was left behind";

  StagedDirectory staged(out);
  write_file_atomic(staged.staging_path() / "x.txt", "2");
  staged.commit();
  EXPECT_EQ(read_file(out / "x.txt"), "2");
}

TEST_F(FilesTest, StagedDirectoryRefusesNonEmptyUnlessOverwrite) {
  const fs::path out = dir_ / "ep";
  fs::create_directories(out);
  write_file_atomic(out / "old.txt", "old");
  write_file_atomic(out / "segment.json", "{}");  // marks it as a result proprio wrote
  EXPECT_THROW(StagedDirectory{out}, Error);
  StagedDirectory staged(out, /*overwrite=*/true);
  write_file_atomic(staged.staging_path() / "new.txt", "new");
  staged.commit();
  EXPECT_FALSE(fs::exists(out / "old.txt"));
  EXPECT_TRUE(fs::exists(out / "new.txt"));
}

// Issue 16: a FIFO given as an input hung the reader; /dev/zero was read for ever.
TEST_F(FilesTest, RefusesFifosAndDevicesWithoutBlocking) {
  const fs::path fifo = dir_ / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Run in another thread so that a regression fails the test instead of hanging it.
  auto read_fifo = std::async(std::launch::async, [&] {
    try {
      read_file(fifo);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("read");
  });
  ASSERT_EQ(read_fifo.wait_for(std::chrono::seconds(10)), std::future_status::ready)
      << "read_file blocked on a FIFO";
  EXPECT_EQ(read_fifo.get(), fifo.string() + ": is not a regular file (a FIFO, device or socket)");
  EXPECT_THROW(read_file("/dev/zero"), Error);
  EXPECT_THROW(read_file_head("/dev/zero", 24), Error);
  EXPECT_THROW(regular_file_size(fifo), Error);
}

TEST_F(FilesTest, RefusesFilesOverTheCapBeforeReading) {
  const fs::path p = dir_ / "big";
  write_file_atomic(p, "0123456789");
  EXPECT_EQ(read_file(p, 10), "0123456789");
  EXPECT_THROW(read_file(p, 9), Error);
  EXPECT_EQ(read_file_head(p, 4), "0123");
  EXPECT_EQ(read_file_head(p, 40), "0123456789");
  EXPECT_EQ(regular_file_size(p), 10U);
  // A sparse file past the default cap is refused from its size alone.
  const fs::path huge = dir_ / "huge";
  write_file_atomic(huge, "x");
  fs::resize_file(huge, kMaxReadBytes + 1);
  try {
    read_file(huge);
    FAIL() << "read a file over the cap";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("more than the"), std::string::npos) << e.what();
  }
}

// Issue 16: --overwrite deleted any directory; core's message told every command to pass --force.
TEST_F(FilesTest, OverwriteReplacesOnlyADirectoryProprioWrote) {
  const fs::path out = dir_ / "photos";
  fs::create_directories(out);
  write_file_atomic(out / "holiday.jpg", "not ours");
  try {
    StagedDirectory staged(out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pass --overwrite"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("--force"), std::string::npos) << e.what();
  }
  EXPECT_THROW(StagedDirectory(out, /*overwrite=*/true), Error);
  EXPECT_TRUE(fs::exists(out / "holiday.jpg"));
  // An empty directory is fine without --overwrite.
  fs::create_directories(dir_ / "empty");
  StagedDirectory empty(dir_ / "empty");
  empty.commit();
}

// Issue 16: a kill -9 left temporary files and staging directories that nothing removed.
TEST_F(FilesTest, StaleTemporariesOfKilledWritersAreRemovedByTheNextWrite) {
  // Process id 999999999 is above any pid_max: the writer is gone. Process 1 is alive.
  write_file_atomic(dir_ / "a.txt.tmp-999999999-0-1f", "half");
  write_file_atomic(dir_ / "a.txt.tmp-1-0-1f", "another writer's, alive");
  fs::create_directories(dir_ / ".ep.tmp-999999999-3-ab" / "frames");
  fs::create_directories(dir_ / "ep.tmp-999999999-4-cd.old");
  write_file_atomic(dir_ / "a.txt", "new");
  EXPECT_FALSE(fs::exists(dir_ / "a.txt.tmp-999999999-0-1f"));
  EXPECT_TRUE(fs::exists(dir_ / "a.txt.tmp-1-0-1f"));
  StagedDirectory staged(dir_ / "ep");
  EXPECT_FALSE(fs::exists(dir_ / ".ep.tmp-999999999-3-ab"));
  EXPECT_FALSE(fs::exists(dir_ / "ep.tmp-999999999-4-cd.old"));
}

// Issue 16: a legal long name failed because of the temporary suffix.
TEST_F(FilesTest, LongNamesUpToTheFileSystemLimitAreWritable) {
  const std::string name(255, 'n');
  write_file_atomic(dir_ / name, "long");
  EXPECT_EQ(read_file(dir_ / name), "long");
  StagedDirectory staged(dir_ / std::string(255, 'd'));
  write_file_atomic(staged.staging_path() / "x", "1");
  staged.commit();
  EXPECT_TRUE(fs::exists(dir_ / std::string(255, 'd') / "x"));
}

TEST_F(FilesTest, ReplacingADirectoryLeavesNothingBeside) {
  const fs::path out = dir_ / "ep";
  fs::create_directories(out);
  write_file_atomic(out / "episode.json", "{}");
  StagedDirectory staged(out, /*overwrite=*/true);
  write_file_atomic(staged.staging_path() / "episode.json", "[]");
  staged.commit();
  EXPECT_EQ(read_file(out / "episode.json"), "[]");
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
  EXPECT_EQ(n, 1);
}

// Issue 16: `segment ep --out ep --overwrite` deleted its input; `--model m --json m` wrote over
// the model.
TEST_F(FilesTest, AnOutputThatIsAnInputIsRefused) {
  const fs::path ep = dir_ / "ep";
  fs::create_directories(ep);
  write_file_atomic(ep / "arm.csv", "t\n");
  EXPECT_THROW(require_output_not_input(ep, {ep}, "--out"), Error);
  EXPECT_THROW(require_output_not_input(dir_ / "ep/", {ep}, "--out"), Error);
  EXPECT_THROW(require_output_not_input(dir_ / "x/../ep", {ep}, "--out"), Error);
  EXPECT_THROW(require_output_not_input(dir_, {ep / "arm.csv"}, "--out"), Error);
  fs::create_directory_symlink(ep, dir_ / "link");
  EXPECT_THROW(require_output_not_input(dir_ / "link", {ep}, "--out"), Error);
  fs::create_hard_link(ep / "arm.csv", dir_ / "hard.csv");
  EXPECT_THROW(require_output_not_input(dir_ / "hard.csv", {ep / "arm.csv"}, "--out"), Error);
  // Not yet written outputs compare by name.
  EXPECT_THROW(require_output_not_input(dir_ / "m.bin", {dir_ / "m.bin"}, "--json"), Error);
  EXPECT_NO_THROW(require_output_not_input(dir_ / "seg", {ep}, "--out"));
  EXPECT_NO_THROW(require_output_not_input(ep / "seg", {ep / "arm.csv"}, "--out"));
  EXPECT_NO_THROW(require_output_not_input(dir_ / "m.json", {dir_ / "m.bin", {}}, "--json"));
}

TEST_F(FilesTest, OverwriteTakesTheWritersOwnMarkers) {
  const fs::path run = dir_ / "run";
  write_file_atomic(run / "push.json", "{}");
  constexpr std::string_view kMarkers[] = {"learn.json", "episode/episode.json"};
  // push.json is not one of these markers: refused, untouched, naming the markers.
  try {
    StagedDirectory s(run, true, kMarkers);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("learn.json or episode/episode.json"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::exists(run / "push.json"));
  write_file_atomic(run / "episode" / "episode.json", "{}");
  StagedDirectory s(run, true, kMarkers);
  write_file_atomic(s.staging_path() / "learn.json", "{}");
  s.commit();
  EXPECT_TRUE(fs::exists(run / "learn.json"));
  EXPECT_FALSE(fs::exists(run / "push.json"));
}

// The atomic exchange under SIGKILL (issue 16): a forked child replaces a directory of four files
// in a loop (each generation's files all hold its number); the parent kills it at a random moment
// (seeded) and checks that the path holds one whole generation, never nothing or a mix, and that
// the staging directories a killed child leaves are removed by the next writer there.
TEST_F(FilesTest, ADirectoryReplacedInALoopAndKilledAtRandomIsAlwaysWhole) {
  const fs::path out = dir_ / "result";
  constexpr std::array<const char*, 4> kFiles{"summary.json", "a.txt", "b.txt", "c.txt"};
  auto write_generation = [&](long g) {
    StagedDirectory s(out, true);
    for (const char* f : kFiles) write_file_atomic(s.staging_path() / f, std::to_string(g));
    s.commit();
  };
  auto hidden = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir_)) n += e.path().filename().string()[0] == '.';
    return n;
  };
  write_generation(0);
  std::mt19937 rng(20261202);
  std::uniform_int_distribution<int> delay_us(0, 60000);
  constexpr int kKills = 120;
  int killed_with_leftovers = 0;
  std::set<std::string> generations;
  for (int i = 0; i < kKills; ++i) {
    // The child says when its first generation is whole, and the random delay runs from there:
    // on a loaded machine (CI under ASan) a delay from the fork alone may end before any write.
    std::array<int, 2> ready{};
    ASSERT_EQ(::pipe(ready.data()), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      ::close(ready[0]);
      try {
        for (long g = 1 + (1000000L * i);; ++g) {
          write_generation(g);
          if (ready[1] >= 0) {
            const char one = 1;
            if (::write(ready[1], &one, 1) != 1) ::_exit(4);
            ::close(ready[1]);
            ready[1] = -1;
          }
        }
      } catch (...) {
        ::_exit(3);
      }
    }
    ::close(ready[1]);
    char got = 0;
    const auto n = ::read(ready[0], &got, 1);  // 0 only if the child ended: checked below
    ::close(ready[0]);
    (void)n;
    std::this_thread::sleep_for(std::chrono::microseconds(delay_us(rng)));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the writer ended by itself at kill " << i;
    // The path holds one whole generation.
    ASSERT_TRUE(fs::is_directory(out)) << "missing after kill " << i;
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(out)) names.insert(e.path().filename().string());
    ASSERT_EQ(names.size(), kFiles.size()) << "kill " << i;
    const std::string g = read_file(out / kFiles[0]);
    for (const char* f : kFiles) ASSERT_EQ(read_file(out / f), g) << "kill " << i << ", " << f;
    generations.insert(g);
    killed_with_leftovers += hidden() > 0;
  }
  // The next write removes what the killed writers left beside the path.
  write_generation(-1);
  EXPECT_EQ(hidden(), 0);
  EXPECT_EQ(read_file(out / "a.txt"), "-1");
  // The kills fell at different moments: the path was replaced between kills (each write syncs
  // five files; each child finished one before its delay began), and some kills left a
  // staging directory behind (a kill in the middle of a replacement).
  EXPECT_GE(generations.size(), 5U);
  EXPECT_GT(killed_with_leftovers, 0);
  std::printf("%d kills: %zu generations seen, %d kills left staging leftovers\n", kKills,
              generations.size(), killed_with_leftovers);
}

}  // namespace
}  // namespace proprio::core
