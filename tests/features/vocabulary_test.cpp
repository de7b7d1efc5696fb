#include "proprio/features/vocabulary.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "../support/hex_bytes.hpp"
#include "nearest.hpp"
#include "proprio/core/random.hpp"
#include "test_util.hpp"

namespace proprio::features {
namespace {

using test::expect_error;

cv::Mat random_matrix(int rows, int cols, std::uint64_t seed) {
  cv::Mat m(rows, cols, CV_32F);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, 255);
  return m;
}

int brute_force(const cv::Mat& words, const cv::Mat& x, int i) {
  int best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (int k = 0; k < words.rows; ++k) {
    const double d = cv::norm(words.row(k), x.row(i), cv::NORM_L2SQR);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  return best;
}

TEST(Vocabulary, QuantizeEqualsBruteForce) {
  // Sizes that fill no panel, exactly one, and several with a remainder; odd dimensions too.
  for (const auto& [K, D] : std::vector<std::pair<int, int>>{
           {1, 128}, {7, 128}, {32, 128}, {1001, 128}, {50, 3}, {33, 17}}) {
    const cv::Mat words = random_matrix(K, D, 10 + K);
    const cv::Mat x = random_matrix(1237, D, 20 + K);
    const Vocabulary v(words);
    EXPECT_EQ(v.size(), K);
    std::vector<float> sq;
    const auto ids = v.quantize(x, sq, 2);
    ASSERT_EQ(ids.size(), 1237U);
    int same = 0;
    for (int i = 0; i < x.rows; ++i) {
      const int bf = brute_force(words, x, i);
      const int got = ids[static_cast<std::size_t>(i)];
      // Float rounding may pick an equally near word; then the distances agree.
      const double dbf = cv::norm(words.row(bf), x.row(i), cv::NORM_L2SQR);
      const double dgot = cv::norm(words.row(got), x.row(i), cv::NORM_L2SQR);
      EXPECT_NEAR(dgot, dbf, 1e-4 * dbf + 1e-3) << "K " << K << " row " << i;
      EXPECT_NEAR(sq[static_cast<std::size_t>(i)], dgot, 1e-4 * dgot + 1e-2);
      same += got == bf;
      EXPECT_EQ(v.quantize(x.ptr<float>(i)), bf);
    }
    EXPECT_GE(same, x.rows - 2) << "K " << K;
  }
}

TEST(Vocabulary, SecondNearestFromTheKernel) {
  const cv::Mat words = random_matrix(45, 128, 1);
  const cv::Mat x = random_matrix(100, 128, 2);
  const auto packed = detail::pack_centres(words.ptr<float>(), 45, 128);
  std::vector<int> best(100);
  std::vector<float> b(100);
  std::vector<float> s(100);
  detail::nearest_centres(x.ptr<float>(), 100, packed, best.data(), b.data(), s.data());
  for (int i = 0; i < 100; ++i) {
    std::vector<double> d;
    for (int k = 0; k < 45; ++k) d.push_back(cv::norm(words.row(k), x.row(i), cv::NORM_L2SQR));
    std::sort(d.begin(), d.end());
    EXPECT_NEAR(b[static_cast<std::size_t>(i)], d[0], 1e-4 * d[0]);
    EXPECT_NEAR(s[static_cast<std::size_t>(i)], d[1], 1e-4 * d[1]);
  }
}

TEST(Vocabulary, BagOfWords) {
  const cv::Mat words = random_matrix(20, 128, 3);
  const Vocabulary v(words);
  cv::Mat x;
  for (const int k : {3, 3, 19, 0}) x.push_back(words.row(k));
  EXPECT_EQ(bag_of_words(v, x), (std::vector<std::int32_t>{3, 3, 19, 0}));
  EXPECT_TRUE(bag_of_words(v, cv::Mat(0, 128, CV_32F)).empty());
  expect_error([&] { (void)v.quantize(random_matrix(3, 64, 1)); }, "64 columns");
  cv::Mat nan = x.clone();
  nan.at<float>(1, 1) = std::numeric_limits<float>::quiet_NaN();
  expect_error([&] { (void)v.quantize(nan); }, "non-finite");
  expect_error([&] { Vocabulary bad(nan); }, "non-finite");
  expect_error([&] { Vocabulary empty{cv::Mat()}; }, "empty");
}

TEST(VocabularyFile, ReadsAndWritesTheBytesOfVersion1) {
  // A 2 x 3 vocabulary as the first version of the writer saved it (docs/formats/vocabulary.md).
  const std::string v1 = proprio::test::bytes_from_hex(
      "5052564f4341423101000000054fc738ca000000000000000200000003000000"
      "a60000000000803f0000004000004040000090400000a0c00000c0407b22636f"
      "6d6d616e645f6c696e65223a2270726f7072696f20766f636162206275696c64"
      "222c22637265617465645f757463223a22323032362d31312d32325430363a30"
      "303a30305a222c226769745f636f6d6d6974223a22222c226d756a6f636f5f76"
      "657273696f6e223a22222c226f70656e63765f76657273696f6e223a22222c22"
      "70726f7072696f5f76657273696f6e223a22302e312e30222c2273656564223a"
      "377d");
  const auto path = test::temp_path("v1.vocab");
  test::spill(path, v1);
  const cv::Mat words = (cv::Mat_<float>(2, 3) << 1, 2, 3, 4.5f, -5, 6);
  EXPECT_EQ(cv::norm(read_vocabulary(path).words(), words, cv::NORM_INF), 0);
  const auto p = read_vocabulary_provenance(path);
  EXPECT_EQ(p.command_line, "proprio vocab build");
  EXPECT_EQ(p.seed, std::optional<std::uint64_t>(7));
  write_vocabulary(path, Vocabulary(words), p);
  EXPECT_EQ(test::slurp(path), v1);
}

TEST(VocabularyFile, RoundTripAndCorruption) {
  const cv::Mat words = random_matrix(400, 128, 4);
  const auto path = test::temp_path("v.vocab");
  auto prov = core::Provenance::current({"proprio", "vocab", "build"}, 42);
  write_vocabulary(path, Vocabulary(words), prov);
  const Vocabulary v = read_vocabulary(path);
  EXPECT_EQ(cv::norm(v.words(), words, cv::NORM_INF), 0);
  const auto p = read_vocabulary_provenance(path);
  EXPECT_EQ(p.seed, std::optional<std::uint64_t>(42));
  EXPECT_EQ(p.command_line, prov.command_line);

  const std::string bytes = test::slurp(path);
  for (const std::size_t cut :
       {std::size_t{0}, std::size_t{10}, std::size_t{30}, bytes.size() - 1}) {
    test::spill(path, bytes.substr(0, cut));
    expect_error([&] { read_vocabulary(path); }, cut < 24 ? "truncated header" : "truncated");
  }
  test::spill(path, bytes + "x");
  expect_error([&] { read_vocabulary(path); }, "corrupt");
  for (const std::size_t at : {std::size_t{40}, bytes.size() / 2, bytes.size() - 3}) {
    std::string flipped = bytes;
    flipped[at] ^= 0x01;
    test::spill(path, flipped);
    expect_error([&] { read_vocabulary(path); }, "checksum");
  }
  std::string other = bytes;
  other[8] = 9;  // version 9
  test::spill(path, other);
  expect_error([&] { read_vocabulary(path); }, "version 9");
  other = bytes;
  other[0] = 'X';
  test::spill(path, other);
  expect_error([&] { read_vocabulary(path); }, "wrong magic");
  expect_error([&] { read_vocabulary(test::temp_path("nope.vocab")); }, "nope.vocab");
}

}  // namespace
}  // namespace proprio::features
