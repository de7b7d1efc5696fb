#pragma once
// Shared plumbing of the proprio CLI: each verb group registers its subcommands on the root app.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::app {

/// What every command may need from the invocation itself.
struct Invocation {
  std::vector<std::string> argv;

  /// This run's provenance, with the versions of the OpenCV and MuJoCo the CLI links.
  [[nodiscard]] core::Provenance provenance(std::optional<std::uint64_t> seed = {}) const;
};

/// Writes a result document ({"format", "format_version", "provenance", ...figures}) to `path`
/// atomically, unless `path` is empty.
void write_json_result(const std::string& path, const core::Json& document);

/// Registers the verb groups (one file each).
void register_calib_commands(CLI::App& root, const Invocation& inv);
void register_episode_commands(CLI::App& root, const Invocation& inv);
void register_lda_commands(CLI::App& root, const Invocation& inv);
void register_intercept_commands(CLI::App& root, const Invocation& inv);
void register_sim_commands(CLI::App& root, const Invocation& inv);
void register_segment_commands(CLI::App& root, const Invocation& inv);
void register_vocab_commands(CLI::App& root, const Invocation& inv);
void register_recognition_commands(CLI::App& root, const Invocation& inv);
void register_experiment_commands(CLI::App& root, const Invocation& inv);
void register_mot_commands(CLI::App& root, const Invocation& inv);
/// After register_segment_commands (it adds `evaluate push` to `evaluate`).
void register_push_commands(CLI::App& root, const Invocation& inv);
void register_selfsupervise_commands(CLI::App& root, const Invocation& inv);
void register_report_commands(CLI::App& root, const Invocation& inv);
void register_learn_commands(CLI::App& root, const Invocation& inv);

}  // namespace proprio::app
