// Every writer of the CLI refuses an output that is one of its inputs (issue 16): exit 2, one line
// naming the option, before any work is done and without touching the input.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/files.hpp"
#include "proprio/sim/recorder.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::line_count;
using test::run_cli;

// A scratch directory with an image folder (images/a/x.png) and input files made on request.
class OutputsCli : public ::testing::Test {
 protected:
  OutputsCli() {
    fs::create_directories(dir.path() / "images" / "a");
    core::write_file_atomic(dir.path() / "images" / "a" / "x.png", "not read");
  }
  /// An input file `name` holding "input NAME" (made on first use), as a path string.
  std::string file(const std::string& name) const {
    const fs::path p = dir.path() / name;
    if (!fs::exists(p)) core::write_file_atomic(p, "input " + name + "\n");
    return p.string();
  }
  /// Each command exits 2 with one line on stderr that holds its expected words.
  static void expect_refused(const std::vector<std::pair<std::string, std::string>>& cases) {
    for (const auto& [args, expect] : cases) {
      const auto r = run_cli(args);
      EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
      EXPECT_EQ(line_count(r.err), 1) << args << "\n" << r.err;
      EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
    }
  }

  const test::TempDir dir{"proprio_outputs_cli_"};
  const std::string images = (dir.path() / "images").string();
};

TEST_F(OutputsCli, AnOutputThatIsAnInputIsRefusedByEveryWriter) {
  const std::string c1 = file("c1.yml");
  const std::string c2 = file("c2.yml");
  const std::string pts = file("pts.csv");
  const std::string model = file("m.lda");
  const std::string vocab = file("v.vocab");
  const std::string video = sim::RecordOptions::default_background_video().string();
  const std::vector<std::pair<std::string, std::string>> cases{
      {"calib dlt --points " + pts + " --out " + pts, "--out is the same file as"},
      {"calib triangulate --calib1 " + c1 + " --calib2 " + c2 + " --points " + pts + " --out " + c2,
       "--out is the same file as"},
      {"calib triangulate --calib1 " + c1 + " --calib2 " + c2 + " --points " + pts + " --out " +
           (dir.path() / "o.csv").string() + " --json " + pts,
       "--json is the same file as"},
      {"calib backproject --calib " + c1 + " --points " + pts + " --plane 0,0,1,0 --out " + c1,
       "--out is the same file as"},
      {"calib uncertainty --calib1 " + c1 + " --calib2 " + c2 + " --out " +
           (dir.path() / "u.png").string() + " --json " + c2,
       "--json is the same file as"},
      {"calib stereo --images " + images + " --out " + images, "--out is the same file as"},
      {"calib stereo --images " + images + " --out " + dir.path().string(),
       "--out holds the input"},
      {"recognize train --images " + images + " --vocabulary " + vocab + " --model " + vocab,
       "--model is the same file as"},
      {"recognize classify --images " + images + " --vocabulary " + vocab + " --model " + model +
           " --out " + model,
       "--out is the same file as"},
      {"recognize classify --images " + images + " --vocabulary " + vocab + " --model " + model +
           " --json " + vocab,
       "--json is the same file as"},
      {"vocab quantize --vocab " + vocab + " --images " + images + " --corpus " + images,
       "--corpus is the same file as"},
      {"vocab build --images " + images + " --out " + images, "--out is the same file as"},
      {"vocab build --images " + images + " --out " + vocab + " --json " + vocab,
       "--json is the same file as"},
      {"sim calibrate --out " + c1 + " --json " + c1, "--json is the same file as"},
      {"sim record --out " + (dir.path() / "ep").string() + " --json " + video,
       "--json is the same file as"},
  };
  expect_refused(cases);
  for (const auto& name : {"c1.yml", "c2.yml", "pts.csv", "m.lda", "v.vocab"}) {
    EXPECT_EQ(core::read_file(dir.path() / name), std::string("input ") + name + "\n") << name;
  }
  EXPECT_TRUE(fs::exists(dir.path() / "images" / "a" / "x.png"));
  EXPECT_FALSE(fs::exists(dir.path() / "ep"));
}

// mot, push and selfsupervise (issue 16): outputs that are inputs (also through a link), and
// --overwrite of a directory none of them wrote, are refused before any work; nothing is touched.
TEST_F(OutputsCli, MotPushAndSelfsuperviseRefuseInputsAsOutputsAndForeignDirectories) {
  const std::string lda = file("m.lda");
  const std::string vocab = file("v.vocab");
  const std::string mot = file("o.mot");
  const std::string img = file("i.png");
  fs::create_symlink(dir.path() / "m.lda", dir.path() / "link.lda");
  const std::string link = (dir.path() / "link.lda").string();
  const std::string src = " --lda-model " + lda + " --vocabulary " + vocab + " --images " + images;
  // A directory of someone else's, which --overwrite must not replace.
  const fs::path foreign = dir.path() / "foreign";
  fs::create_directories(foreign);
  core::write_file_atomic(foreign / "thesis.tex", "mine\n");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"mot train" + src + " --model " + lda, "--model is the same file as"},
      {"mot train" + src + " --model " + link, "--model is the same file as"},
      {"mot train" + src + " --model " + (dir.path() / "n.mot").string() + " --json " + vocab,
       "--json is the same file as"},
      {"mot train" + src + " --model " + images, "--model is the same file as"},
      {"mot train" + src + " --model " + dir.path().string(), "--model holds the input"},
      {"mot classify" + src + " --model " + mot + " --out " + mot, "--out is the same file as"},
      {"mot classify" + src + " --model " + mot + " --out " + (dir.path() / "c.csv").string() +
           " --json " + (dir.path() / "c.csv").string(),
       "is the same file as"},
      {"mot update" + src + " --model " + mot + " --out " + vocab, "--out is the same file as"},
      {"mot update" + src + " --model " + mot + " --out " + mot + " --json " + mot,
       "is the same file as"},
      {"mot maps --lda-model " + lda + " --vocabulary " + vocab + " --image " + img + " --out " +
           dir.path().string(),
       "--out holds the input"},
      {"mot info --model " + mot + " --json " + mot, "--json is the same file as"},
      {"push --out " + (dir.path() / "p").string() + " --json " + (dir.path() / "p").string(),
       "--json is the same file as"},
      {"push --out " + foreign.string() + " --overwrite", "not a directory proprio push wrote"},
      {"push --out " + lda + " --overwrite", "is not a directory"},
      {"selfsupervise --model " + lda + " --vocabulary " + vocab + " --out " + dir.path().string(),
       "--out holds the input"},
      {"selfsupervise --model " + link + " --vocabulary " + vocab + " --out " + lda,
       "--out is the same file as"},
      {"selfsupervise --model " + lda + " --vocabulary " + vocab + " --out " +
           (dir.path() / "s").string() + " --json " + vocab,
       "--json is the same file as"},
      {"selfsupervise --model " + lda + " --vocabulary " + vocab + " --out " + foreign.string() +
           " --overwrite",
       "not a directory proprio selfsupervise wrote"},
  };
  expect_refused(cases);
  for (const auto& name : {"m.lda", "v.vocab", "o.mot", "i.png"}) {
    EXPECT_EQ(core::read_file(dir.path() / name), std::string("input ") + name + "\n") << name;
  }
  EXPECT_EQ(core::read_file(foreign / "thesis.tex"), "mine\n");
  EXPECT_FALSE(fs::exists(dir.path() / "p"));
  EXPECT_FALSE(fs::exists(dir.path() / "s"));
  EXPECT_FALSE(fs::exists(dir.path() / "n.mot"));
}

// Every command takes --json from one helper (app/cli.hpp's JsonFlag): the same help, and a --json
// that names one of the command's inputs is refused before any work, also by the commands that
// did not check it before the helper (lda perplexity and topics, episode info and check,
// segment, evaluate segmentation, learn, report).
TEST_F(OutputsCli, EveryJsonFlagIsTheSharedOneAndRefusesAnInput) {
  const std::string model = file("m.lda");
  const std::string corpus = file("c.txt");
  const std::vector<std::pair<std::string, std::string>> cases{
      {"lda topics --model " + model + " --json " + model, "--json is the same file as"},
      {"lda perplexity --corpus " + corpus + " --model " + model + " --json " + corpus,
       "--json is the same file as"},
      {"episode info " + images + " --json " + images, "--json is the same file as"},
      {"episode check " + images + " --json " + images, "--json is the same file as"},
      {"segment " + images + " --out " + (dir.path() / "o").string() + " --json " + images,
       "--json is the same file as"},
      {"evaluate segmentation " + images + " --out " + (dir.path() / "e").string() + " --json " +
           images,
       "--json is the same file as"},
      {"learn --out " + (dir.path() / "l").string() + " --json " + (dir.path() / "l").string(),
       "--json is the same file as"},
  };
  expect_refused(cases);
  EXPECT_EQ(core::read_file(dir.path() / "m.lda"), "input m.lda\n");
  EXPECT_EQ(core::read_file(dir.path() / "c.txt"), "input c.txt\n");
  for (const char* command :
       {"calib dlt", "episode info", "lda train", "lda topics", "mot info", "push", "segment",
        "evaluate segmentation", "sim dataset", "vocab build", "recognize classify",
        "experiment scatter", "learn", "report", "intercept", "selfsupervise"}) {
    const auto r = run_cli(std::string(command) + " --help");
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_NE(r.out.find("as JSON to this file (atomically; never one of the command's inputs"),
              std::string::npos)
        << command << "\n"
        << r.out;
  }
}

}  // namespace
}  // namespace proprio
