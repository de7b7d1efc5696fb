#include "proprio/features/vocabulary.hpp"

#include <cmath>

#include "nearest.hpp"
#include "proprio/core/binary_file.hpp"
#include "proprio/core/parallel.hpp"
#include "proprio/features/features.hpp"

namespace proprio::features {
namespace fs = std::filesystem;
using core::put_binary;

namespace {

constexpr core::BinaryFormat kFormat{"PRVOCAB1", kVocabularyFormatVersion, "vocabulary"};

void check_matrix(const cv::Mat& m, int dimension, const std::string& what) {
  if (m.empty()) throw Error(what + ": empty matrix");
  if (m.type() != CV_32F || m.dims != 2) throw Error(what + ": must be a float32 matrix");
  if (dimension > 0 && m.cols != dimension) {
    throw Error(what + ": " + std::to_string(m.cols) + " columns where the vocabulary has " +
                std::to_string(dimension));
  }
  if (!cv::checkRange(m, true)) throw Error(what + ": holds non-finite values (NaN or inf)");
}

struct Parsed {
  cv::Mat words;
  core::Provenance provenance;
};

Parsed parse(const fs::path& path) {
  const std::string payload = core::read_binary_file(path, kFormat);
  core::BinaryReader r(payload, path, kFormat.kind);
  const auto k = r.get<std::uint32_t>("the word count");
  const auto d = r.get<std::uint32_t>("the dimension");
  const auto json_size = r.get<std::uint32_t>("the provenance size");
  if (k == 0 || d == 0 || k > 10'000'000 || d > 100'000 ||
      static_cast<std::uint64_t>(k) * d * 4 + json_size != r.left()) {
    throw Error::in_file(path, "corrupt vocabulary file: " + std::to_string(k) + " words of " +
                                   std::to_string(d) + " values do not fill its " +
                                   std::to_string(r.left()) + " bytes");
  }
  Parsed p;
  p.words.create(static_cast<int>(k), static_cast<int>(d), CV_32F);
  const auto data = r.take(static_cast<std::size_t>(k) * d * 4, "the words");
  std::memcpy(p.words.data, data.data(), data.size());
  if (!cv::checkRange(p.words, true)) {
    throw Error::in_file(path, "corrupt vocabulary file: non-finite values in the words");
  }
  const auto text = r.take(json_size, "the provenance");
  try {
    p.provenance = core::provenance_from_json(core::parse_json(text, path), path.string());
  } catch (const core::Json::exception& e) {
    throw Error::in_file(path, std::string("corrupt vocabulary file: bad provenance: ") + e.what());
  }
  return p;
}

}  // namespace

Vocabulary::Vocabulary(cv::Mat words) : words_(std::move(words)) {
  check_matrix(words_, 0, "vocabulary");
  if (!words_.isContinuous()) words_ = words_.clone();
  norms_.resize(static_cast<std::size_t>(words_.rows));
  for (int k = 0; k < words_.rows; ++k)
    norms_[static_cast<std::size_t>(k)] = static_cast<float>(words_.row(k).dot(words_.row(k)));
}

int Vocabulary::quantize(const float* descriptor) const {
  // -2 x.c + ||c||^2: one pass over the words, no square roots.
  int best = 0;
  float best_score = 0;
  const int D = dimension();
  for (int k = 0; k < size(); ++k) {
    const float* c = words_.ptr<float>(k);
    float dot = 0;
    for (int d = 0; d < D; ++d) dot += descriptor[d] * c[d];
    const float s = norms_[static_cast<std::size_t>(k)] - 2 * dot;
    if (k == 0 || s < best_score) {
      best = k;
      best_score = s;
    }
  }
  return best;
}

std::vector<int> Vocabulary::quantize(const cv::Mat& descriptors, int threads) const {
  std::vector<float> sq;
  return quantize(descriptors, sq, threads);
}

std::vector<int> Vocabulary::quantize(const cv::Mat& descriptors, std::vector<float>& sq_dist,
                                      int threads) const {
  std::vector<int> ids;
  sq_dist.clear();
  if (descriptors.rows == 0) return ids;
  check_matrix(descriptors, dimension(), "quantize");
  const cv::Mat x = descriptors.isContinuous() ? descriptors : descriptors.clone();
  // Packing costs one pass over the words; it is redone per call so that a Vocabulary stays a
  // plain value (the words are few next to the descriptors of any real call).
  const auto packed = detail::pack_centres(words_.ptr<float>(), size(), dimension());
  const auto n = static_cast<std::size_t>(x.rows);
  ids.resize(n);
  sq_dist.resize(n);
  constexpr std::size_t kBlock = 2048;
  const std::size_t tasks = (n + kBlock - 1) / kBlock;
  core::parallel_for(tasks, threads, [&](std::size_t t, int) {
    const std::size_t a = t * kBlock;
    const std::size_t m = std::min(kBlock, n - a);
    detail::nearest_centres(x.ptr<float>(static_cast<int>(a)), m, packed, ids.data() + a,
                            sq_dist.data() + a, nullptr);
  });
  return ids;
}

std::vector<std::int32_t> bag_of_words(const Vocabulary& vocabulary, const cv::Mat& descriptors) {
  const auto ids = vocabulary.quantize(descriptors);
  return {ids.begin(), ids.end()};
}

void write_vocabulary(const fs::path& path, const Vocabulary& vocabulary,
                      const core::Provenance& provenance) {
  const std::string json = core::to_json(provenance).dump();
  const cv::Mat& w = vocabulary.words();
  std::string payload;
  put_binary<std::uint32_t>(payload, static_cast<std::uint32_t>(w.rows));
  put_binary<std::uint32_t>(payload, static_cast<std::uint32_t>(w.cols));
  put_binary<std::uint32_t>(payload, static_cast<std::uint32_t>(json.size()));
  payload.append(reinterpret_cast<const char*>(w.data), w.total() * sizeof(float));
  payload += json;
  core::write_binary_file(path, kFormat, payload);
}

Vocabulary read_vocabulary(const fs::path& path) { return Vocabulary(parse(path).words); }

core::Provenance read_vocabulary_provenance(const fs::path& path) { return parse(path).provenance; }

std::string VocabularyInfo::brief() const {
  std::string s = vocabulary.string();
  s += ": ";
  s += std::to_string(words);
  s += " words of ";
  s += std::to_string(dimension);
  s += " values, written ";
  s += built_by.created_utc;
  s += " by proprio ";
  s += built_by.proprio_version;
  s += "\n  ";
  s += built_by.command_line;
  return s;
}

VocabularyInfo run_vocabulary_info(const fs::path& path, const core::Provenance& provenance) {
  auto parsed = parse(path);
  const Vocabulary vocabulary(parsed.words);  // the same checks as read_vocabulary
  VocabularyInfo r;
  r.vocabulary = path;
  r.words = vocabulary.size();
  r.dimension = vocabulary.dimension();
  r.built_by = std::move(parsed.provenance);
  r.document = core::result_document("proprio.vocab.info", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

}  // namespace proprio::features
