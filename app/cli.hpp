#pragma once
// Shared plumbing of the proprio CLI: each verb group registers its subcommands on the root app.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
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

/// The `--json FILE` option every command takes: the call's record (its `document`: "format",
/// "format_version", "provenance", then the Result's described fields) written atomically after
/// the call. One flag name and help form, one refusal of a FILE that is one of the command's
/// inputs or other outputs (made before the call, so that a run never replaces what it reads),
/// one atomic write. A command whose outputs depend on the run (`experiment scatter --seeds`)
/// makes one JsonFlag per output with its path.
class JsonFlag {
 public:
  JsonFlag() = default;
  explicit JsonFlag(std::string path) : path_(std::move(path)) {}

  /// Adds `--json FILE` to `cmd`: "Also write WHAT as JSON to this file (atomically; ...)".
  void add_to(CLI::App* cmd, const std::string& what);
  /// Throws Error when FILE is one of `others` (the command's inputs and its other outputs; a
  /// directory holding one counts too); nothing when --json was not given.
  void refuse(const std::vector<std::filesystem::path>& others) const;
  /// Writes `document` to FILE atomically; nothing when --json was not given.
  void write(const core::Json& document) const;

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] bool given() const { return !path_.empty(); }

 private:
  std::string path_;
};

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
