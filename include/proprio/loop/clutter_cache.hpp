#pragma once
// The cache of `proprio experiment clutter` (loop/clutter_experiment.hpp) as read back: a trial's
// manifest (CACHE/seed_S/OBJECT_tT/clutter_cache.json, format kClutterCacheFormat) and a segmented
// push's views (views_dense.bin, views_sparse.bin beside its episode). Both are outside input: a
// cache may be damaged or hand-edited. Separate from the experiment so that the readers are unit
// tested and fuzzed (tests/fuzz/fuzz_clutter_cache.cpp) without a simulator; the push record
// (ClutterPush) is here too, which ClutterExperimentResult lists.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "proprio/core/json_io.hpp"

namespace proprio::loop {

/// The manifest of a cached trial or held-out set (CACHE/seed_S/*/clutter_cache.json).
inline constexpr const char* kClutterCacheFormat = "proprio.experiment.clutter.cache";
inline constexpr int kClutterCacheVersion = 1;

/// One recorded push (from the cache's manifests).
struct ClutterPush {
  std::uint64_t seed = 0;
  std::string object;
  int trial = 0;
  int index = 0;
  std::string outcome;  ///< PushOutcome's name
  bool moved_intended = false;
  bool only_intended = false;
  int replaced = 0;  ///< times the scene was re-placed because the object was not seen
  int attempts = 1;  ///< planning attempts made (ClutterExperimentOptions::attempts)
  /// The outcome of every attempt that was not executed (in order), "off-table" for an object
  /// found off the table.
  std::vector<std::string> failed;
  std::string episode;  ///< relative to the cache (empty: no push executed)
};

/// A segmented push's views at every fraction: descriptors per view (CV_32F, 128 columns).
using ClutterViews = std::vector<std::vector<cv::Mat>>;

/// Views files: "PCLV", version (u32), the key's size (u32) and bytes (the options that shape the
/// views, as JSON), the number of fractions (u32), then per fraction the number of views (u32)
/// and per view rows (u32), cols (u32, 128) and rows x cols float32; little-endian (the host's).
inline constexpr char kClutterViewsMagic[4] = {'P', 'C', 'L', 'V'};
inline constexpr std::uint32_t kClutterViewsVersion = 1;
inline constexpr std::uint32_t kClutterViewsMaxViews = 100000;  ///< per fraction
inline constexpr std::uint32_t kClutterViewsMaxRows = 1000000;  ///< descriptors per view

/// The views file's bytes.
std::string clutter_views_bytes(std::string_view key, const ClutterViews& views);

/// Parses a views file's bytes: nullopt (recompute) unless the magic, the version, the key and the
/// number of fractions are these and every size fits in the bytes that follow (checked in that
/// order, each before anything is allocated) with nothing after the last view.
std::optional<ClutterViews> parse_clutter_views(std::string_view bytes, std::string_view key,
                                                std::size_t fractions);

/// Reads a views file (core::read_file's checks): nullopt when it is missing or parse_clutter_views
/// refuses it.
std::optional<ClutterViews> read_clutter_views(const std::filesystem::path& file,
                                               std::string_view key, std::size_t fractions);

/// Writes a views file atomically.
void write_clutter_views(const std::filesystem::path& file, std::string_view key,
                         const ClutterViews& views);

/// Whether a cached directory's manifest is this experiment's: kOtherFormat unless it is an object
/// whose "format" is kClutterCacheFormat and "format_version" kClutterCacheVersion (checked first,
/// of any type); kOtherOptions unless its "recording" equals `recording`.
enum class ClutterManifestMatch { kYes, kOtherFormat, kOtherOptions };
ClutterManifestMatch match_clutter_manifest(const core::Json& manifest,
                                            const core::Json& recording);

/// The largest number of pushes a trial's manifest may list.
inline constexpr std::size_t kClutterManifestMaxPushes = 10000;

/// The pushes a trial's manifest lists (its "pushes" array), for `seed`, `object` and `trial`.
/// Each push's episode, when not empty, is relative to the trial's directory and must stay inside
/// it (no absolute path, no ".."); ClutterPush::episode is then `trial_dir` (relative to the
/// cache) / episode. Throws Error naming `file` and the push for a member missing, of the wrong
/// type or out of range, or more than kClutterManifestMaxPushes pushes.
std::vector<ClutterPush> clutter_manifest_pushes(const core::Json& manifest,
                                                 const std::filesystem::path& file,
                                                 std::uint64_t seed, const std::string& object,
                                                 int trial, const std::filesystem::path& trial_dir);

}  // namespace proprio::loop
