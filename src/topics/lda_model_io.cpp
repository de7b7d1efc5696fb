#include "proprio/topics/lda_model_io.hpp"

#include <cstring>

#include "proprio/core/binary_file.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::topics {
namespace fs = std::filesystem;
using core::put_binary;

namespace {

// Version 1: no word weights; 2: the word weights after lambda. A model without weights is
// written as version 1, so that older builds still read it.
constexpr core::BinaryFormat kFormat{"PRLDAMDL", kLdaModelFormatVersion, "LDA model", 1};
constexpr core::BinaryFormat kFormatV1{"PRLDAMDL", 1, "LDA model"};

bool plain_token(const std::string& w) {
  if (w.empty() || w[0] == '#') return false;
  for (const char c : w) {
    if (c == ',' || c == '"' || c == ' ' || c == '\t' || c == '\r' || c == '\n') return false;
  }
  return true;
}

}  // namespace

std::string serialize_lda_model(const LdaModel& model) {
  std::string payload;
  const auto K = static_cast<std::uint32_t>(model.num_topics());
  const auto W = static_cast<std::uint32_t>(model.num_words());
  payload.reserve(64 + static_cast<std::size_t>(K) * W * 8 + static_cast<std::size_t>(W) * 12);
  put_binary(payload, K);
  put_binary(payload, W);
  put_binary(payload, model.alpha);
  put_binary(payload, model.eta);
  put_binary(payload, model.tau0);
  put_binary(payload, model.kappa);
  put_binary(payload, static_cast<std::int64_t>(model.updates));
  put_binary(payload, static_cast<std::int64_t>(model.total_documents));
  put_binary(payload, static_cast<std::uint32_t>(model.vocabulary.size()));
  for (const auto& w : model.vocabulary) {
    put_binary(payload, static_cast<std::uint32_t>(w.size()));
    payload += w;
  }
  const auto* data = reinterpret_cast<const char*>(model.lambda.data());
  payload.append(data, static_cast<std::size_t>(model.lambda.size()) * sizeof(double));
  if (model.word_weights.empty()) return core::frame_binary(kFormatV1, payload);
  for (const std::int32_t w : model.word_weights) put_binary(payload, w);
  return core::frame_binary(kFormat, payload);
}

LdaModel parse_lda_model(std::string_view bytes, const fs::path& source) {
  core::BinaryReader r(core::unframe_binary(bytes, kFormat, source), source, kFormat.kind);
  const bool weighted = core::framed_version(bytes) >= 2;
  LdaModel m;
  const auto K = r.get<std::uint32_t>("K");
  const auto W = r.get<std::uint32_t>("W");
  m.alpha = r.get<double>("alpha");
  m.eta = r.get<double>("eta");
  m.tau0 = r.get<double>("tau0");
  m.kappa = r.get<double>("kappa");
  m.updates = r.get<std::int64_t>("the update count");
  m.total_documents = r.get<std::int64_t>("the document count");
  const auto V = r.get<std::uint32_t>("the vocabulary size");
  if (K == 0 || W == 0 || K > 100000 || W > static_cast<std::uint32_t>(INT32_MAX) ||
      (V != 0 && V != W) || static_cast<std::uint64_t>(K) * W * 8 > r.left()) {
    throw Error::in_file(source, "corrupt LDA model file: sizes K = " + std::to_string(K) +
                                     ", W = " + std::to_string(W) + ", vocabulary " +
                                     std::to_string(V));
  }
  m.vocabulary.reserve(V);
  for (std::uint32_t i = 0; i < V; ++i) {
    const auto n = r.get<std::uint32_t>("a word's length");
    m.vocabulary.emplace_back(r.take(n, "a word"));
  }
  const std::uint64_t weights_bytes = weighted ? std::uint64_t{W} * 4 : 0;
  if (static_cast<std::uint64_t>(K) * W * 8 + weights_bytes != r.left()) {
    throw Error::in_file(source, "corrupt LDA model file: lambda has the wrong size");
  }
  m.lambda.resize(K, W);
  const auto data = r.take(static_cast<std::size_t>(K) * W * 8, "lambda");
  std::memcpy(m.lambda.data(), data.data(), data.size());
  if (weighted) {
    m.word_weights.resize(W);
    for (auto& w : m.word_weights) w = r.get<std::int32_t>("a word weight");
  }
  try {
    m.validate();
  } catch (const Error& e) {
    throw Error::in_file(source, e.what());
  }
  return m;
}

void save_lda_model(const LdaModel& model, const fs::path& path) {
  model.validate();
  core::write_file_atomic(path, serialize_lda_model(model));
}

LdaModel load_lda_model(const fs::path& path) {
  // The header first: a big file of another kind is refused before its body is read.
  const std::uintmax_t size = core::check_binary_file_header(path, kFormat);
  return parse_lda_model(core::read_file(path, size), path);
}

void write_lambda_csv(const LdaModel& model, const fs::path& path, bool normalize) {
  const int K = model.num_topics();
  const int W = model.num_words();
  bool named = !model.vocabulary.empty();
  for (const auto& w : model.vocabulary) named = named && plain_token(w);
  std::vector<std::string> header(static_cast<std::size_t>(W));
  for (int w = 0; w < W; ++w) {
    auto& h = header[static_cast<std::size_t>(w)];
    if (named) {
      h = model.vocabulary[static_cast<std::size_t>(w)];
    } else {
      h = std::to_string(w);
      h.insert(h.begin(), 'w');
    }
  }
  std::vector<std::vector<std::optional<double>>> rows(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) {
    const double sum = normalize ? model.lambda.row(k).sum() : 1.0;
    auto& row = rows[static_cast<std::size_t>(k)];
    row.resize(static_cast<std::size_t>(W));
    for (int w = 0; w < W; ++w) row[static_cast<std::size_t>(w)] = model.lambda(k, w) / sum;
  }
  core::write_file_atomic(path, core::format_csv(header, rows));
}

LdaModel read_lambda_csv(const fs::path& path, double alpha, double eta) {
  const core::CsvTable t = core::read_csv(path);
  const std::size_t W = t.header.size();
  LdaModel m;
  m.alpha = alpha;
  m.eta = eta;
  m.lambda.resize(static_cast<Eigen::Index>(t.rows.size()), static_cast<Eigen::Index>(W));
  for (std::size_t k = 0; k < t.rows.size(); ++k) {
    if (t.rows[k].size() != W) {
      throw Error::at_line(
          path, t.lines[k],
          "expected " + std::to_string(W) + " values, found " + std::to_string(t.rows[k].size()));
    }
    for (std::size_t w = 0; w < W; ++w) {
      const double v = t.at(k, w);
      if (!(v > 0)) {
        throw Error::at_line(path, t.lines[k],
                             "lambda must be positive, found " + std::to_string(v) + " in column " +
                                 std::to_string(w + 1));
      }
      m.lambda(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(w)) = v;
    }
  }
  if (m.lambda.rows() == 0) throw Error::in_file(path, "no topics (no rows)");
  try {
    m.validate();
  } catch (const Error& e) {
    throw Error::in_file(path, e.what());
  }
  return m;
}

}  // namespace proprio::topics
