#pragma once
// Saving and loading LDA models (docs/formats/lda-model.md): a versioned binary file with a
// CRC-32 over its contents, written atomically, and the K x W lambda as CSV for other tools.

#include <filesystem>
#include <string>
#include <string_view>

#include "proprio/topics/lda_model.hpp"

namespace proprio::topics {

/// The newest version of the binary model format, the one a model with word weights is written
/// in (2); a model without them is written as version 1, and this build reads both.
inline constexpr std::uint32_t kLdaModelFormatVersion = 2;

/// The model as the bytes of the binary format.
std::string serialize_lda_model(const LdaModel& model);
/// Parses the binary format; `source` names the file in errors. Throws Error on a wrong magic
/// number or version, a truncated or padded file, a checksum mismatch, or an invalid model.
LdaModel parse_lda_model(std::string_view bytes, const std::filesystem::path& source);

/// Writes the model atomically.
void save_lda_model(const LdaModel& model, const std::filesystem::path& path);
/// Reads and checks a model file.
LdaModel load_lda_model(const std::filesystem::path& path);

/// Writes lambda as CSV, one topic a row and one word a column (header: the vocabulary's words
/// when they are plain tokens, else w0, w1, ...); with `normalize`, each row is divided by its
/// sum (the topic's word probabilities).
void write_lambda_csv(const LdaModel& model, const std::filesystem::path& path, bool normalize);

/// Reads a K x W lambda written by write_lambda_csv or by another tool (a header line, then K
/// rows of W positive numbers) into a model with the given priors. Throws Error naming the file
/// and line on a bad value.
LdaModel read_lambda_csv(const std::filesystem::path& path, double alpha, double eta);

}  // namespace proprio::topics
