#include "proprio/topics/mot_model_io.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "proprio/core/binary_file.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::topics {
namespace fs = std::filesystem;
using core::put_binary;

namespace {

constexpr core::BinaryFormat kFormat{"PRMOTMDL", kMotModelFormatVersion, "Mixture of Topics model"};
/// Version 1: as version 2 without the trailing theta smoothing.
constexpr core::BinaryFormat kFormatV1{"PRMOTMDL", 1, "Mixture of Topics model"};
/// Version 2: as version 3 without the mixture components after each object.
constexpr core::BinaryFormat kFormatV2{"PRMOTMDL", 2, "Mixture of Topics model"};

/// The format version in a file's header, when the header is there and its magic is ours.
std::uint32_t header_version(std::string_view bytes) {
  std::uint32_t v = 0;
  if (bytes.size() >= 12 && bytes.substr(0, 8) == kFormat.magic)
    std::memcpy(&v, bytes.data() + 8, 4);
  return v;
}

/// Bytes of one object's record besides its name: name length, views, count, T mean logs, T
/// alphas (and from version 3 the number of mixture components).
std::uint64_t object_bytes(std::uint64_t topics, bool components) {
  return 4 + 8 + 8 + 16 * topics + (components ? 4 : 0);
}
/// Bytes of one mixture component: weight, count, T mean logs, T alphas.
std::uint64_t component_bytes(std::uint64_t topics) { return 8 + 8 + 16 * topics; }

std::string hex(std::uint32_t v) {
  std::ostringstream s;
  s << std::hex;
  s.width(8);
  s.fill('0');
  s << v;
  return s.str();
}

std::string describe(const MotBasis& b) {
  std::string s = "LDA model " + hex(b.lda_checksum) + " (" + std::to_string(b.lda_topics) +
                  " topics, " + std::to_string(b.lda_words) + " words)";
  if (b.has_vocabulary) s += " and vocabulary " + hex(b.vocabulary_checksum);
  return s;
}

}  // namespace

std::uint32_t lda_model_checksum(const LdaModel& model) {
  const std::string bytes = serialize_lda_model(model);
  std::uint32_t crc = 0;
  std::memcpy(&crc, bytes.data() + 12, sizeof crc);
  return crc;
}

MotBasis mot_basis(const LdaModel& lda, const std::uint32_t* vocabulary_checksum) {
  MotBasis b;
  b.lda_checksum = lda_model_checksum(lda);
  b.lda_topics = lda.num_topics();
  b.lda_words = lda.num_words();
  if (vocabulary_checksum != nullptr) {
    b.has_vocabulary = true;
    b.vocabulary_checksum = *vocabulary_checksum;
  }
  return b;
}

void check_mot_basis(const MotBasis& basis, const LdaModel& lda,
                     const std::uint32_t* vocabulary_checksum, const fs::path& source) {
  MotBasis now = mot_basis(lda, vocabulary_checksum);
  bool same = now.lda_checksum == basis.lda_checksum && now.lda_topics == basis.lda_topics &&
              now.lda_words == basis.lda_words;
  if (basis.has_vocabulary && now.has_vocabulary) {
    same = same && now.vocabulary_checksum == basis.vocabulary_checksum;
  } else {
    now.has_vocabulary = false;
  }
  if (!same) {
    throw Error::in_file(source, "this Mixture of Topics model was built on " + describe(basis) +
                                     ", not on " + describe(now) +
                                     ": its Dirichlets do not apply to that theta");
  }
}

std::string serialize_mot_model(const MotModel& model, const MotBasis& basis) {
  model.validate();
  const int t = model.num_topics();
  require(t == basis.lda_topics, "Mixture of Topics model of " + std::to_string(t) +
                                     " topics recorded as built on an LDA model of " +
                                     std::to_string(basis.lda_topics));
  std::string payload;
  put_binary(payload, static_cast<std::uint32_t>(t));
  put_binary(payload, static_cast<std::uint32_t>(model.num_classes()));
  put_binary(payload, static_cast<std::uint32_t>(model.prior == MotPrior::kUniform ? 1 : 0));
  put_binary(payload, basis.lda_checksum);
  put_binary(payload, static_cast<std::uint32_t>(basis.lda_words));
  put_binary(payload, static_cast<std::uint32_t>(basis.has_vocabulary ? 1 : 0));
  put_binary(payload, basis.vocabulary_checksum);
  for (const auto& o : model.objects) {
    require(o.name.size() <= kMotMaxNameBytes, "Mixture of Topics model: object name longer than " +
                                                   std::to_string(kMotMaxNameBytes) + " bytes");
    require(o.stats.dim() == t && o.stats.count() > 0,
            "Mixture of Topics model: object '" + o.name + "' has no statistics to save");
    put_binary(payload, static_cast<std::uint32_t>(o.name.size()));
    payload += o.name;
    put_binary(payload, o.views);
    put_binary(payload, o.stats.count());
    for (int k = 0; k < t; ++k) put_binary(payload, o.stats.mean_log()(k));
    for (int k = 0; k < t; ++k) put_binary(payload, o.dirichlet.alpha()(k));
    require(
        o.mixture.num_components() <= static_cast<int>(kMotMaxComponents),
        "Mixture of Topics model: more than " + std::to_string(kMotMaxComponents) + " components");
    put_binary(payload, static_cast<std::uint32_t>(o.mixture.num_components()));
    for (const auto& c : o.mixture.components) {
      require(c.stats.dim() == t && c.stats.count() > 0,
              "Mixture of Topics model: a component of '" + o.name + "' has no statistics");
      put_binary(payload, c.weight);
      put_binary(payload, c.stats.count());
      for (int k = 0; k < t; ++k) put_binary(payload, c.stats.mean_log()(k));
      for (int k = 0; k < t; ++k) put_binary(payload, c.dirichlet.alpha()(k));
    }
  }
  require(model.smoothing >= 0.0 && model.smoothing <= 0.5,
          "Mixture of Topics model: smoothing outside [0, 0.5]");
  put_binary(payload, model.smoothing);
  return core::frame_binary(kFormat, payload);
}

MotModelFile parse_mot_model(std::string_view bytes, const fs::path& source) {
  const std::uint32_t version = header_version(bytes);
  const bool v1 = version == 1;
  const bool has_components = version != 1 && version != 2;
  const core::BinaryFormat& format = v1 ? kFormatV1 : version == 2 ? kFormatV2 : kFormat;
  core::BinaryReader r(core::unframe_binary(bytes, format, source), source, kFormat.kind);
  const std::uint64_t trailer = v1 ? 0 : 8;  // the smoothing after the objects
  const auto t = r.get<std::uint32_t>("T");
  const auto c = r.get<std::uint32_t>("C");
  const auto prior = r.get<std::uint32_t>("the prior");
  MotModelFile out;
  out.basis.lda_checksum = r.get<std::uint32_t>("the LDA checksum");
  const auto words = r.get<std::uint32_t>("the LDA words");
  const auto has_vocabulary = r.get<std::uint32_t>("the vocabulary flag");
  out.basis.vocabulary_checksum = r.get<std::uint32_t>("the vocabulary checksum");
  auto corrupt = [&](const std::string& what) {
    return Error::in_file(source, "corrupt Mixture of Topics model file: " + what);
  };
  if (t < 2 || t > kMotMaxTopics || c < 1 || c > kMotMaxClasses ||
      static_cast<std::uint64_t>(c) * object_bytes(t, has_components) + trailer > r.left()) {
    throw corrupt("sizes T = " + std::to_string(t) + ", C = " + std::to_string(c) + " for " +
                  std::to_string(r.left()) + " bytes");
  }
  if (prior > 1 || has_vocabulary > 1 || words < 1 ||
      words > static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::max())) {
    throw corrupt("prior " + std::to_string(prior) + ", vocabulary flag " +
                  std::to_string(has_vocabulary) + ", LDA words " + std::to_string(words));
  }
  out.basis.lda_topics = static_cast<int>(t);
  out.basis.lda_words = static_cast<int>(words);
  out.basis.has_vocabulary = has_vocabulary == 1;
  out.model.prior = prior == 1 ? MotPrior::kUniform : MotPrior::kViews;
  out.model.objects.reserve(c);
  for (std::uint32_t i = 0; i < c; ++i) {
    const auto n = r.get<std::uint32_t>("a name's length");
    if (n > kMotMaxNameBytes) throw corrupt("object name of " + std::to_string(n) + " bytes");
    std::string name(r.take(n, "a name"));
    const auto views = r.get<double>("views");
    const auto count = r.get<double>("a count");
    if (!(std::isfinite(views) && views > 0 && std::isfinite(count) && count > 0)) {
      throw corrupt("object '" + name + "' has views " + std::to_string(views) + ", count " +
                    std::to_string(count));
    }
    Eigen::VectorXd mean_log(t);
    Eigen::VectorXd alpha(t);
    for (std::uint32_t k = 0; k < t; ++k) mean_log(k) = r.get<double>("a mean log");
    for (std::uint32_t k = 0; k < t; ++k) alpha(k) = r.get<double>("an alpha");
    if (!mean_log.allFinite()) throw corrupt("object '" + name + "' has a non-finite mean log");
    DirichletStats stats;
    try {
      stats.add_log(mean_log, count);
      out.model.objects.push_back({std::move(name), std::move(stats), Dirichlet(alpha), views});
    } catch (const Error& e) {
      throw corrupt(e.what());
    }
    if (!has_components) continue;
    MotObject& o = out.model.objects.back();
    const auto m = r.get<std::uint32_t>("the number of components");
    if (m > kMotMaxComponents ||
        static_cast<std::uint64_t>(m) * component_bytes(t) +
                static_cast<std::uint64_t>(c - 1 - i) * object_bytes(t, true) + trailer >
            r.left()) {
      throw corrupt("object '" + o.name + "' claims " + std::to_string(m) + " components for " +
                    std::to_string(r.left()) + " bytes");
    }
    for (std::uint32_t j = 0; j < m; ++j) {
      const auto weight = r.get<double>("a component weight");
      const auto cn = r.get<double>("a component count");
      for (std::uint32_t k = 0; k < t; ++k) mean_log(k) = r.get<double>("a mean log");
      for (std::uint32_t k = 0; k < t; ++k) alpha(k) = r.get<double>("an alpha");
      if (!(std::isfinite(weight) && weight > 0 && std::isfinite(cn) && cn > 0) ||
          !mean_log.allFinite()) {
        throw corrupt("object '" + o.name + "', component " + std::to_string(j) + ": weight " +
                      std::to_string(weight) + ", count " + std::to_string(cn) +
                      " or a mean log not finite");
      }
      try {
        DirichletStats cs;
        cs.add_log(mean_log, cn);
        o.mixture.components.push_back({weight, std::move(cs), Dirichlet(alpha)});
      } catch (const Error& e) {
        throw corrupt(e.what());
      }
    }
    if (m > 0) {
      try {
        o.mixture.validate();
      } catch (const Error& e) {
        throw corrupt("object '" + o.name + "': " + e.what());
      }
    }
  }
  if (!v1) {
    const auto smoothing = r.get<double>("the smoothing");
    if (!(smoothing >= 0.0 && smoothing <= 0.5)) {
      throw corrupt("theta smoothing " + std::to_string(smoothing) + " outside [0, 0.5]");
    }
    out.model.smoothing = smoothing;
  }
  if (r.left() != 0) throw corrupt(std::to_string(r.left()) + " bytes after the last object");
  return out;
}

void save_mot_model(const MotModel& model, const MotBasis& basis, const fs::path& path) {
  core::write_file_atomic(path, serialize_mot_model(model, basis));
}

MotModelFile load_mot_model(const fs::path& path) {
  return parse_mot_model(core::read_file(path), path);
}

}  // namespace proprio::topics
