#pragma once
// Saving and loading Mixture of Topics models (thesis 7.1; docs/formats/mot-model.md): the
// project's framed binary file (core/binary_file.hpp: magic "PRMOTMDL", version, CRC-32, payload
// size), written atomically, that records what the model was built on: the checksum, topics and
// words of the LDA model whose theta it models and the checksum of the visual vocabulary. Theta
// from another LDA model or vocabulary means nothing to the Dirichlets, so using the model with
// them is an error (check_mot_basis).

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/mixture_of_topics.hpp"

namespace proprio::topics {

/// The version of the binary MoT model format this build writes. It reads this one, version 2
/// (no mixture components: every object one Dirichlet) and version 1 (neither components nor
/// theta smoothing: read as MotModel::smoothing = 0); other versions are refused.
inline constexpr std::uint32_t kMotModelFormatVersion = 3;

/// Bounds a reader enforces before allocating (hostile files are normal input).
inline constexpr std::uint32_t kMotMaxTopics = 100000;
inline constexpr std::uint32_t kMotMaxClasses = 100000;
inline constexpr std::uint32_t kMotMaxNameBytes = 1024;
inline constexpr std::uint32_t kMotMaxComponents = 1000;  ///< per object

/// What a MoT model was built on.
struct MotBasis {
  std::uint32_t lda_checksum = 0;         ///< lda_model_checksum of the LDA model
  int lda_topics = 0;                     ///< its K (= the MoT's T)
  int lda_words = 0;                      ///< its W
  bool has_vocabulary = false;            ///< whether a visual vocabulary was recorded
  std::uint32_t vocabulary_checksum = 0;  ///< its checksum (features::vocabulary_checksum)

  bool operator==(const MotBasis&) const = default;
};

/// The identity of an LDA model: the CRC-32 of its binary serialisation (the checksum in the
/// header of its model file, lda-model.md), so any change of lambda, priors or words changes it.
std::uint32_t lda_model_checksum(const LdaModel& model);

/// The basis of a model built on `lda` (and, when given, a vocabulary of that checksum).
MotBasis mot_basis(const LdaModel& lda, const std::uint32_t* vocabulary_checksum = nullptr);

/// Throws Error naming `source` unless `lda` (and the vocabulary checksum, when both the basis
/// and the caller have one) is what `basis` recorded: "built on LDA model <crc> (K topics, W
/// words), not on this one (<crc>, ...)".
void check_mot_basis(const MotBasis& basis, const LdaModel& lda,
                     const std::uint32_t* vocabulary_checksum, const std::filesystem::path& source);

/// A model file's contents.
struct MotModelFile {
  MotModel model;
  MotBasis basis;
};

/// The model as the bytes of the binary format. Throws Error when the model is invalid, a name is
/// longer than kMotMaxNameBytes, or T differs from basis.lda_topics.
std::string serialize_mot_model(const MotModel& model, const MotBasis& basis);
/// Parses the binary format; `source` names the file in errors. Throws Error on a wrong magic
/// number or version, a truncated or padded file, a checksum mismatch, a size out of bounds or
/// larger than the bytes there (checked before any allocation), or an invalid model (alpha not
/// positive and finite, views not positive, non-finite statistics).
MotModelFile parse_mot_model(std::string_view bytes, const std::filesystem::path& source);

/// Writes the model atomically.
void save_mot_model(const MotModel& model, const MotBasis& basis,
                    const std::filesystem::path& path);
/// Reads and checks a model file.
MotModelFile load_mot_model(const std::filesystem::path& path);

}  // namespace proprio::topics
