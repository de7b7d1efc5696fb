#pragma once
// A folder-per-class image set (thesis 6.3.3): each object alone on the table, seen from many
// viewpoints and turned to many poses, over real photographs as backdrops; the ground-truth
// views the thesis photographed, and a stand-in for Caltech-style sets.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "proprio/sim/object_catalogue.hpp"

namespace proprio::sim {

struct ViewsOptions {
  std::vector<std::string> objects{"book", "mug"};  ///< catalogue names, one folder each
  int per_object = 100;                             ///< images per object
  int width = 320;                                  ///< image size, pixels
  int height = 240;
  std::uint64_t seed = 1;
  /// Backdrop photographs (opencv-doc samples by default), one drawn at random per image.
  std::vector<std::filesystem::path> backgrounds = default_backgrounds();
  /// Camera distance to the object, m, and elevation above the table, degrees (uniform ranges).
  double min_distance = 0.35, max_distance = 0.7;
  double min_elevation_deg = 10, max_elevation_deg = 60;
  /// Also the object's ground-truth mask, as each PNG's alpha channel (255 on the object's
  /// pixels, 0 elsewhere; the colours under alpha 0 are the backdrop, kept): the analogue of a
  /// robot's view cut out by its segmentation mask. Feature options `--alpha-mask` read it. The
  /// colours are the same as without it (the same draws, the same renders).
  bool masks = false;

  static std::vector<std::filesystem::path> default_backgrounds();
  /// Throws Error naming the bad option (unknown objects are found by render_views).
  void validate() const;
};

struct ViewsSummary {
  int images = 0;
  std::string message;
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

/// Writes out/<object>/000000.png ... for every object (atomically: out appears only when
/// complete). Each image: the object alone at a random yaw, the camera at a random azimuth in
/// the front half, distance and elevation, looking at the object, over a random backdrop. Throws
/// Error for an unknown object, an unreadable photograph or an existing `out`.
ViewsSummary render_views(const std::filesystem::path& out, const ViewsOptions& options,
                          const ObjectCatalogue& catalogue);

}  // namespace proprio::sim
