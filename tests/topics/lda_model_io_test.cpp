// Model files: round trips, and every truncation and every flipped byte is a clear Error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../support/hex_bytes.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::topics {
namespace {
namespace fs = std::filesystem;

LdaModel small_model() {
  LdaModel m;
  m.lambda.resize(3, 4);
  m.lambda << 1, 2, 3, 4, 0.5, 0.25, 7, 8, 9, 10, 11, 0.125;
  m.alpha = 0.1;
  m.eta = 0.01;
  m.tau0 = 1.0;
  m.kappa = 0.7;
  m.updates = 12;
  m.total_documents = 300;
  m.vocabulary = {"cat", "dog", "emu", "gnu"};
  return m;
}

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("proprio_lda_io_" + std::to_string(::getpid()) + "_" + name);
}

TEST(LdaModelIo, RoundTripsExactly) {
  const LdaModel m = small_model();
  const fs::path p = temp("m.lda");
  save_lda_model(m, p);
  const LdaModel back = load_lda_model(p);
  EXPECT_TRUE(back == m);
  LdaModel no_vocab = m;
  no_vocab.vocabulary.clear();
  EXPECT_TRUE(parse_lda_model(serialize_lda_model(no_vocab), "x") == no_vocab);
  fs::remove(p);
}

// small_model() with word weights: the last two words (say, colour words) count 3 times.
LdaModel weighted_model() {
  LdaModel m = small_model();
  m.word_weights = {1, 1, 3, 3};
  return m;
}

// A model with word weights is written as version 2 (the weights after lambda, int32 each) and
// reads back with them; one without is written as version 1, which older builds read.
TEST(LdaModelIo, WordWeightsRoundTripInVersion2) {
  const LdaModel m = weighted_model();
  const std::string bytes = serialize_lda_model(m);
  EXPECT_EQ(bytes[8], 2);
  EXPECT_EQ(serialize_lda_model(small_model())[8], 1);
  EXPECT_EQ(bytes.size(), serialize_lda_model(small_model()).size() + 4 * 4);
  const LdaModel back = parse_lda_model(bytes, "w.lda");
  EXPECT_TRUE(back == m);
  EXPECT_FALSE(back == small_model());
  const fs::path p = temp("w.lda");
  save_lda_model(m, p);
  EXPECT_TRUE(load_lda_model(p) == m);
  fs::remove(p);
  // Every truncation and flipped bit of the version 2 file is an error too.
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_THROW((void)parse_lda_model(std::string_view(bytes).substr(0, n), "w.lda"), Error) << n;
  }
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string bad = bytes;
    bad[i] = static_cast<char>(static_cast<unsigned char>(bad[i]) ^ 0x01U);
    EXPECT_THROW((void)parse_lda_model(bad, "w.lda"), Error) << "byte " << i;
  }
}

TEST(LdaModelIo, WordWeightsOutOfBoundsAreRefused) {
  LdaModel m = weighted_model();
  m.word_weights[1] = 0;
  EXPECT_THROW(save_lda_model(m, temp("bad.lda")), Error);
  m.word_weights[1] = kMaxWordWeight + 1;
  EXPECT_THROW(m.validate(), Error);
  m.word_weights = {1, 2, 3};  // 3 weights for 4 words
  try {
    m.validate();
    ADD_FAILURE() << "3 weights for 4 words";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("3 word weights for 4 words"), std::string::npos);
  }
  m.word_weights = {1, kMaxWordWeight, 1, 1};
  EXPECT_NO_THROW(m.validate());
  EXPECT_FALSE(fs::exists(temp("bad.lda")));
}

TEST(LdaModelIo, ReadsAndWritesTheBytesOfVersion1) {
  // small_model() as the first version of the writer saved it (docs/formats/lda-model.md).
  const std::string v1 = test::bytes_from_hex(
      "50524c44414d444c01000000e12ba3d5b8000000000000000300000004000000"
      "9a9999999999b93f7b14ae47e17a843f000000000000f03f666666666666e63f"
      "0c000000000000002c0100000000000004000000030000006361740300000064"
      "6f6703000000656d7503000000676e75000000000000f03f000000000000e03f"
      "00000000000022400000000000000040000000000000d03f0000000000002440"
      "00000000000008400000000000001c4000000000000026400000000000001040"
      "0000000000002040000000000000c03f");
  EXPECT_TRUE(parse_lda_model(v1, "v1.lda") == small_model());
  EXPECT_EQ(serialize_lda_model(small_model()), v1);
}

TEST(LdaModelIo, EveryTruncationIsAnError) {
  const std::string bytes = serialize_lda_model(small_model());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    try {
      parse_lda_model(std::string_view(bytes).substr(0, n), "m.lda");
      ADD_FAILURE() << "truncated to " << n << " bytes was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("m.lda: ", 0), 0u) << e.what();
    }
  }
  EXPECT_NE(std::string(bytes + "x").size(), bytes.size());
  EXPECT_THROW(parse_lda_model(bytes + "x", "m.lda"), Error);
}

TEST(LdaModelIo, EveryFlippedByteIsAnError) {
  const std::string bytes = serialize_lda_model(small_model());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (const unsigned char mask : {0x01, 0x80}) {
      std::string bad = bytes;
      bad[i] = static_cast<char>(static_cast<unsigned char>(bad[i]) ^ mask);
      EXPECT_THROW(parse_lda_model(bad, "m.lda"), Error) << "byte " << i;
    }
  }
}

TEST(LdaModelIo, NamesTheProblem) {
  const std::string bytes = serialize_lda_model(small_model());
  auto message = [](const std::string& b) {
    try {
      parse_lda_model(b, "m.lda");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("hello world, this is not a model").find("wrong magic"), std::string::npos);
  std::string v3 = bytes;
  v3[8] = 3;
  EXPECT_NE(message(v3).find("version 3; this build reads versions 1-2"), std::string::npos)
      << message(v3);
  // A version 1 body under a version 2 header has no room for the word weights.
  std::string v2 = bytes;
  v2[8] = 2;
  EXPECT_NE(message(v2).find("wrong size"), std::string::npos) << message(v2);
  std::string flipped = bytes;
  flipped[bytes.size() - 3] ^= 0x10;
  EXPECT_NE(message(flipped).find("checksum"), std::string::npos);
  EXPECT_NE(message(bytes.substr(0, 40)).find("truncated"), std::string::npos);
  EXPECT_THROW(load_lda_model(temp("missing.lda")), Error);
}

// Issue 16: a model with an absurd alpha (or lambda) was read, and infer wrote rows of -nan.
TEST(LdaModelIo, AModelThatWouldGiveNanIsRefusedWhenRead) {
  auto refused = [](const LdaModel& m, const std::string& fragment) {
    try {
      (void)parse_lda_model(serialize_lda_model(m), "m.lda");
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "read a model with " << fragment;
  };
  LdaModel m = small_model();
  m.alpha = 1e300;
  refused(m, "m.lda: LDA model: alpha = ");
  m = small_model();
  m.eta = 1e7;
  refused(m, "eta = ");
  m = small_model();
  m.lambda(2, 3) = 1e200;
  refused(m, "lambda(2, 3)");
  m = small_model();
  m.alpha = kMaxLdaPrior;
  EXPECT_NO_THROW((void)parse_lda_model(serialize_lda_model(m), "m.lda"));
}

TEST(LdaModelIo, RefusesToSaveAnInvalidModel) {
  LdaModel m = small_model();
  m.lambda(1, 1) = std::nan("");
  EXPECT_THROW(save_lda_model(m, temp("bad.lda")), Error);
  m = small_model();
  m.vocabulary.pop_back();
  EXPECT_THROW(save_lda_model(m, temp("bad.lda")), Error);
  EXPECT_FALSE(fs::exists(temp("bad.lda")));
}

TEST(LdaModelIo, LambdaCsvRoundTripsAndNormalizes) {
  const LdaModel m = small_model();
  const fs::path p = temp("lambda.csv");
  write_lambda_csv(m, p, false);
  const std::string text = core::read_file(p);
  EXPECT_EQ(text.substr(0, text.find('\n')), "cat,dog,emu,gnu");
  const LdaModel back = read_lambda_csv(p, 0.1, 0.01);
  EXPECT_TRUE(back.lambda == m.lambda);
  write_lambda_csv(m, p, true);
  const LdaModel norm = read_lambda_csv(p, 0.1, 0.01);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(norm.lambda.row(k).sum(), 1.0, 1e-15);
  LdaModel odd = m;
  odd.vocabulary[1] = "a,b";
  write_lambda_csv(odd, p, false);
  const std::string t2 = core::read_file(p);
  EXPECT_EQ(t2.substr(0, t2.find('\n')), "w0,w1,w2,w3");
  std::ofstream(p) << "w0,w1\n1,2\n3,-1\n";
  try {
    read_lambda_csv(p, 0.1, 0.1);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
  }
  std::ofstream(p) << "w0,w1\n1,2\n3,nan\n";
  EXPECT_THROW(read_lambda_csv(p, 0.1, 0.1), Error);
  fs::remove(p);
}

}  // namespace
}  // namespace proprio::topics
