#pragma once
// Checkpoints of resumable learning (issue 16): online LDA and the k-means vocabulary write one
// every N mini-batches or iterations and resume from it; a run killed at any moment and resumed
// ends with the model of the uninterrupted run, bit for bit. The file (docs/formats/checkpoint.md)
// is framed as every binary file (core/binary_file.hpp: magic "PRCHKPNT", version, CRC-32, payload
// size checked against the file's real size before the body is read), written atomically. Payload:
//
//   u32 length, bytes   kind: which learner wrote it ("online_lda", "kmeans")
//   u64                 checksum of the input (the corpus, the descriptors)
//   u32                 number of options that matter, then per option: u32 length, name bytes,
//                       u32 length, value bytes (the value as text, exact: round-trip doubles)
//   u64 length, bytes   the learner's state, laid out by the learner
//
// Every length is checked against the bytes left in the payload before anything is allocated.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "proprio/core/binary_file.hpp"
#include "proprio/core/fields.hpp"

namespace proprio::core {

inline constexpr BinaryFormat kCheckpointFormat{"PRCHKPNT", 1, "checkpoint"};
/// At most this many options in a checkpoint (a bound on the parser's loop).
inline constexpr std::uint32_t kMaxCheckpointOptions = 4096;

/// Where and how often a learner checkpoints, and where it resumes from. Paths are given by the
/// CLI (--checkpoint, --resume); `every` is --checkpoint-every.
struct CheckpointOptions {
  std::filesystem::path checkpoint;  ///< the file to write (atomically); empty: none
  int every = 1;                     ///< a checkpoint every this many mini-batches / iterations
  std::filesystem::path resume;      ///< a checkpoint to resume from; empty: start afresh

  /// Throws Error when every < 1.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.every, {"checkpoint_every",
                   "With --checkpoint: one every this many mini-batches (LDA) or iterations "
                   "(k-means)",
                   core::between(1, 1000000000)});
  }
};

/// One checkpoint: who wrote it, what it was learning from, with which options, and its state.
struct Checkpoint {
  std::string kind;
  std::uint64_t input_checksum = 0;
  std::vector<std::pair<std::string, std::string>> options;
  std::string state;
};

/// FNV-1a (64 bits) of `bytes`, continuing from `hash` (start with the default).
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash = 14695981039346656037ULL);

/// A double as exact text (shortest round trip), for Checkpoint::options.
std::string exact_text(double value);

/// The checkpoint as the bytes of the file (frame included).
std::string serialize_checkpoint(const Checkpoint& checkpoint);
/// Parses a whole file's bytes; throws Error naming `source` on a wrong magic, version, size,
/// checksum, or a length that runs past the end.
Checkpoint parse_checkpoint(std::string_view bytes, const std::filesystem::path& source);
/// Writes atomically (a kill leaves the old checkpoint or the new one).
void save_checkpoint(const Checkpoint& checkpoint, const std::filesystem::path& path);
/// Reads a checkpoint file, its header checked before its body is read.
Checkpoint load_checkpoint(const std::filesystem::path& path);

/// Throws Error naming `source` unless `found` was written by `expected.kind` over the input whose
/// checksum is expected.input_checksum with exactly expected.options (names the first option that
/// differs, or "another corpus" / "other descriptors" as `input_name` says).
void check_checkpoint_matches(const Checkpoint& found, const Checkpoint& expected,
                              const std::filesystem::path& source, std::string_view input_name);

}  // namespace proprio::core
