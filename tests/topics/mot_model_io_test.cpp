// Mixture of Topics model files: a round trip, every truncation and flipped byte an Error, sizes
// bounded before allocating, and the LDA model / vocabulary they were built on enforced.
#include "proprio/topics/mot_model_io.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "../support/error_of.hpp"
#include "../support/temp_dir.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"

namespace proprio::topics {
namespace {

using test::error_of;

::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << '"' << text << "\" does not contain \"" << part << '"';
}

LdaModel small_lda(double shift = 0.0) {
  LdaModel m;
  m.lambda.resize(3, 5);
  for (int k = 0; k < 3; ++k) {
    for (int w = 0; w < 5; ++w) m.lambda(k, w) = 1.0 + k + 0.5 * w + shift;
  }
  m.alpha = 0.3;
  m.eta = 0.1;
  return m;
}

MotModel small_model() {
  core::Rng rng(3);
  Eigen::VectorXd a(3), b(3);
  a << 3.0, 1.0, 0.5;
  b << 0.5, 1.0, 3.0;
  Eigen::MatrixXd theta(40, 3);
  std::vector<int> labels;
  for (int i = 0; i < 40; ++i) {
    theta.row(i) = Dirichlet(i < 20 ? a : b).sample(rng).transpose();
    labels.push_back(i < 20 ? 0 : 1);
  }
  return fit_mot(theta, labels, {"cup", "toy giraffe"}).model;
}

TEST(MotModelIo, RoundTripsExactly) {
  test::TempDir dir("proprio_mot_io_");
  const MotModel m = small_model();
  const std::uint32_t vocab = 0xDEADBEEF;
  const MotBasis basis = mot_basis(small_lda(), &vocab);
  save_mot_model(m, basis, dir.path() / "m.mot");
  const MotModelFile f = load_mot_model(dir.path() / "m.mot");
  EXPECT_EQ(f.basis, basis);
  ASSERT_EQ(f.model.num_classes(), 2);
  EXPECT_EQ(f.model.prior, m.prior);
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(f.model.objects[c].name, m.objects[c].name);
    EXPECT_EQ(f.model.objects[c].dirichlet.alpha(), m.objects[c].dirichlet.alpha());
    EXPECT_EQ(f.model.objects[c].stats.mean_log(), m.objects[c].stats.mean_log());
    EXPECT_EQ(f.model.objects[c].stats.count(), m.objects[c].stats.count());
    EXPECT_EQ(f.model.objects[c].views, m.objects[c].views);
  }
  EXPECT_EQ(serialize_mot_model(f.model, f.basis), serialize_mot_model(m, basis));
}

TEST(MotModelIo, EveryTruncationAndFlippedByteIsAnError) {
  const std::string bytes = serialize_mot_model(small_model(), mot_basis(small_lda()));
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_THROW((void)parse_mot_model(bytes.substr(0, n), "t.mot"), Error) << n;
  }
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (const unsigned char bit : {0x01, 0x80}) {
      std::string b = bytes;
      b[i] = static_cast<char>(static_cast<unsigned char>(b[i]) ^ bit);
      EXPECT_THROW((void)parse_mot_model(b, "t.mot"), Error) << "byte " << i;
    }
  }
  std::string flipped = bytes;
  flipped[bytes.size() - 1] ^= 0x04;
  EXPECT_TRUE(has(error_of([&] { (void)parse_mot_model(flipped, "t.mot"); }), "checksum"));
}

TEST(MotModelIo, HostileSizesAreRefusedBeforeAllocating) {
  // A well-framed file (valid checksum) whose payload claims 100,000 objects of 100,000 topics.
  std::string payload;
  core::put_binary(payload, std::uint32_t{100000});
  core::put_binary(payload, std::uint32_t{100000});
  for (int i = 0; i < 5; ++i) core::put_binary(payload, std::uint32_t{1});
  const std::string file =
      core::frame_binary({"PRMOTMDL", kMotModelFormatVersion, "Mixture of Topics model"}, payload);
  EXPECT_TRUE(
      has(error_of([&] { (void)parse_mot_model(file, "h.mot"); }), "sizes T = 100000, C = 100000"));
  // A negative alpha with a valid checksum.
  std::string good = serialize_mot_model(small_model(), mot_basis(small_lda()));
  std::string body = good.substr(core::kBinaryHeaderBytes);
  const double minus = -1.0;
  std::memcpy(body.data() + body.size() - 8, &minus, 8);
  const std::string bad =
      core::frame_binary({"PRMOTMDL", kMotModelFormatVersion, "Mixture of Topics model"}, body);
  EXPECT_TRUE(has(error_of([&] { (void)parse_mot_model(bad, "h.mot"); }), "corrupt"));
}

TEST(MotModelIo, AnotherLdaModelOrVocabularyIsAnError) {
  const std::uint32_t vocab = 7;
  const MotBasis basis = mot_basis(small_lda(), &vocab);
  EXPECT_NO_THROW(check_mot_basis(basis, small_lda(), &vocab, "m.mot"));
  EXPECT_NO_THROW(check_mot_basis(basis, small_lda(), nullptr, "m.mot"));
  EXPECT_TRUE(has(error_of([&] { check_mot_basis(basis, small_lda(1e-9), &vocab, "m.mot"); }),
                  "was built on LDA model"));
  const std::uint32_t other = 8;
  EXPECT_TRUE(has(error_of([&] { check_mot_basis(basis, small_lda(), &other, "m.mot"); }),
                  "vocabulary 00000007"));
  EXPECT_NE(lda_model_checksum(small_lda()), lda_model_checksum(small_lda(1e-9)));
}

TEST(MotModelIo, RefusesAModelOfAnotherTopicCountThanItsBasis) {
  LdaModel four = small_lda();
  four.lambda.conservativeResize(4, 5);
  four.lambda.row(3).setConstant(2.0);
  EXPECT_TRUE(has(error_of([&] { (void)serialize_mot_model(small_model(), mot_basis(four)); }),
                  "of 3 topics recorded as built on an LDA model of 4"));
}

/// The version 2 payload of a model (no mixture components), as the writer before version 3.
std::string v2_payload(const MotModel& m, const MotBasis& b) {
  std::string p;
  const auto t = static_cast<std::uint32_t>(m.num_topics());
  core::put_binary(p, t);
  core::put_binary(p, static_cast<std::uint32_t>(m.num_classes()));
  core::put_binary(p, static_cast<std::uint32_t>(m.prior == MotPrior::kUniform ? 1 : 0));
  core::put_binary(p, b.lda_checksum);
  core::put_binary(p, static_cast<std::uint32_t>(b.lda_words));
  core::put_binary(p, static_cast<std::uint32_t>(b.has_vocabulary ? 1 : 0));
  core::put_binary(p, b.vocabulary_checksum);
  for (const auto& o : m.objects) {
    core::put_binary(p, static_cast<std::uint32_t>(o.name.size()));
    p += o.name;
    core::put_binary(p, o.views);
    core::put_binary(p, o.stats.count());
    for (std::uint32_t k = 0; k < t; ++k) core::put_binary(p, o.stats.mean_log()(k));
    for (std::uint32_t k = 0; k < t; ++k) core::put_binary(p, o.dirichlet.alpha()(k));
  }
  core::put_binary(p, m.smoothing);
  return p;
}

/// Two objects, the first a mixture of two Dirichlets (fit_mot with components).
MotModel mixture_model() {
  core::Rng rng(5);
  Eigen::VectorXd a(3), b(3), c(3);
  a << 20.0, 1.0, 1.0;
  b << 1.0, 20.0, 1.0;
  c << 1.0, 1.0, 20.0;
  Eigen::MatrixXd theta(300, 3);
  std::vector<int> labels;
  for (int i = 0; i < 300; ++i) {
    const Eigen::VectorXd& alpha = i < 200 ? (i % 2 == 0 ? a : b) : c;
    theta.row(i) = Dirichlet(alpha).sample(rng).transpose();
    labels.push_back(i < 200 ? 0 : 1);
  }
  MotOptions o;
  o.components = 4;
  return fit_mot(theta, labels, {"two-faced", "plain"}, o).model;
}

TEST(MotModelIo, MixtureComponentsRoundTripInVersion3) {
  const MotModel m = mixture_model();
  ASSERT_EQ(m.objects[0].mixture.num_components(), 2);
  ASSERT_EQ(m.objects[1].mixture.num_components(), 0);
  const MotBasis basis = mot_basis(small_lda());
  const std::string bytes = serialize_mot_model(m, basis);
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + 8, 4);
  EXPECT_EQ(version, 3U);
  const MotModelFile f = parse_mot_model(bytes, "m.mot");
  ASSERT_EQ(f.model.objects[0].mixture.num_components(), 2);
  for (std::size_t j = 0; j < 2; ++j) {
    const auto& got = f.model.objects[0].mixture.components[j];
    const auto& want = m.objects[0].mixture.components[j];
    EXPECT_EQ(got.weight, want.weight);
    EXPECT_EQ(got.dirichlet.alpha(), want.dirichlet.alpha());
    EXPECT_EQ(got.stats.count(), want.stats.count());
    EXPECT_EQ(got.stats.mean_log(), want.stats.mean_log());
  }
  EXPECT_EQ(f.model.objects[1].mixture.num_components(), 0);
  EXPECT_EQ(serialize_mot_model(f.model, f.basis), bytes);
  // Every truncation of a file with components is an error too.
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_THROW((void)parse_mot_model(bytes.substr(0, n), "t.mot"), Error) << n;
  }
  // A component count claiming more than the bytes there, with a valid checksum.
  std::string body = bytes.substr(core::kBinaryHeaderBytes);
  const std::size_t first_count = 28 + 4 + 9 + 16 + 48;  // header fields, "two-faced", stats
  const std::uint32_t huge = 999;
  std::memcpy(body.data() + first_count, &huge, 4);
  const std::string bad =
      core::frame_binary({"PRMOTMDL", kMotModelFormatVersion, "Mixture of Topics model"}, body);
  EXPECT_TRUE(has(error_of([&] { (void)parse_mot_model(bad, "h.mot"); }), "999 components"));
}

TEST(MotModelIo, AnotherVersionIsRefused) {
  const std::string bytes = serialize_mot_model(small_model(), mot_basis(small_lda()));
  const std::string v4 = core::frame_binary({"PRMOTMDL", 4, "Mixture of Topics model"},
                                            bytes.substr(core::kBinaryHeaderBytes));
  EXPECT_THROW((void)parse_mot_model(v4, "new.mot"), Error);
}

TEST(MotModelIo, SmoothingRoundTripsAndVersions1And2AreRead) {
  MotModel m = small_model();
  m.smoothing = 0.03;
  const MotBasis basis = mot_basis(small_lda());
  EXPECT_EQ(parse_mot_model(serialize_mot_model(m, basis), "m.mot").model.smoothing, 0.03);
  // Version 2: the objects without component counts, then the smoothing.
  const std::string v2 =
      core::frame_binary({"PRMOTMDL", 2, "Mixture of Topics model"}, v2_payload(m, basis));
  const MotModelFile f2 = parse_mot_model(v2, "v2.mot");
  EXPECT_EQ(f2.model.smoothing, 0.03);
  ASSERT_EQ(f2.model.num_classes(), 2);
  EXPECT_EQ(f2.model.objects[0].dirichlet.alpha(), m.objects[0].dirichlet.alpha());
  EXPECT_EQ(f2.model.objects[0].mixture.num_components(), 0);
  // Version 1: the same payload without the trailing smoothing.
  const std::string payload =
      v2.substr(core::kBinaryHeaderBytes, v2.size() - 8 - core::kBinaryHeaderBytes);
  const std::string v1 = core::frame_binary({"PRMOTMDL", 1, "Mixture of Topics model"}, payload);
  const MotModelFile f = parse_mot_model(v1, "old.mot");
  EXPECT_EQ(f.model.smoothing, 0.0);
  ASSERT_EQ(f.model.num_classes(), 2);
  EXPECT_EQ(f.model.objects[1].dirichlet.alpha(), m.objects[1].dirichlet.alpha());
  // A version 2 payload framed as version 1 has 8 bytes too many; a bad smoothing is corrupt.
  const std::string mixed = core::frame_binary({"PRMOTMDL", 1, "Mixture of Topics model"},
                                               v2.substr(core::kBinaryHeaderBytes));
  EXPECT_TRUE(
      has(error_of([&] { (void)parse_mot_model(mixed, "x.mot"); }), "after the last object"));
  std::string body = v2.substr(core::kBinaryHeaderBytes);
  const double big = 0.6;
  std::memcpy(body.data() + body.size() - 8, &big, 8);
  const std::string bad = core::frame_binary({"PRMOTMDL", 2, "Mixture of Topics model"}, body);
  EXPECT_TRUE(has(error_of([&] { (void)parse_mot_model(bad, "x.mot"); }), "smoothing"));
}

}  // namespace
}  // namespace proprio::topics
