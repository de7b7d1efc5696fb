#pragma once
// Local features of an image as the vocabularies and documents use them (thesis 6.1.1, 7.3.3):
// which kind, where (a mask, a centre crop) and which patches count (contrast). One description
// of the options, so that `vocab build`, `vocab quantize`, `recognize` and `experiment` take the
// same flags and record the same JSON.
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/sift.hpp"

namespace proprio::features {

/// Which local features make the words: dense SIFT on a grid (7.3.3, the default: every part of
/// an object speaks, however plain) or SIFT at detected interest points (6.1.1).
enum class FeatureKind { kDense, kSift };
inline constexpr core::ChoiceNames<FeatureKind, 2> kFeatureKindNames{
    {{"dense", FeatureKind::kDense}, {"sift", FeatureKind::kSift}}};

/// "dense" or "sift"; throws Error otherwise.
FeatureKind parse_feature_kind(const std::string& name);
std::string to_string(FeatureKind kind);

struct ExtractOptions {
  FeatureKind kind = FeatureKind::kDense;
  DenseSiftOptions dense;  ///< step 8 px, patches of 16 px
  SiftOptions sift;
  /// Dense SIFT: grid points whose patch has a grey-level standard deviation below this (0-255
  /// units) are dropped. A flat patch (plain table, empty background) has no gradient, so its
  /// descriptor says nothing, yet it would take one word and swamp the documents; vl_phow of
  /// Bosch et al. drops low-contrast patches for the same reason. 0 keeps every grid point.
  double min_contrast = 2.0;
  /// Keep only the features in the central `center_crop` of the image's width and height (in
  /// (0, 1]; 1 = all). For object-centred pictures (Caltech, the simulator's views) whose
  /// surroundings would otherwise outweigh a small object.
  double center_crop = 1.0;
  /// Image files (folder-per-class sets): keep only the features on the image's alpha channel
  /// (non-zero alpha: the object, as `sim views --masks` writes it, like a robot's view cut out
  /// by its segmentation mask); an image without alpha is an Error naming it. Frames of episodes
  /// have their own masks and ignore it.
  bool alpha_mask = false;

  /// Throws Error naming the first option out of its bounds.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.kind,
             {"kind",
              "dense (SIFT on a grid, 7.3.3) or sift (at interest points, 6.1.1)",
              {},
              nullptr,
              "features"},
             kFeatureKindNames);
    v(self.dense.step, {"step", "Dense SIFT: grid spacing, px", core::between(1, 4096)});
    v(self.dense.size, {"patch", "Dense SIFT: patch side, px", core::positive_at_most(4096)});
    v(self.sift.max_features,
      {"max_features", "SIFT: keep the strongest N per image (0 = all)", core::at_least(0)});
    v(self.min_contrast, {"min_contrast",
                          "Dense SIFT: drop patches whose grey-level standard deviation is below "
                          "this, 0-255 (0 keeps all)",
                          core::between(0, 255)});
    v(self.center_crop,
      {"center_crop", "Keep the features in this central fraction of width and height",
       core::positive_at_most(1)});
    v(self.alpha_mask, {"alpha_mask",
                        "Image files: keep only the features where the image's alpha channel is "
                        "non-zero (sim views --masks)"});
  }
};

/// Features of an 8-bit grey or BGR image; with `mask` (CV_8U of the image's size, or empty for
/// the whole image) only those whose (rounded) location has a non-zero mask pixel. Dense SIFT
/// computes descriptors only at the kept grid points.
Features extract_features(const cv::Mat& image, const ExtractOptions& options,
                          const cv::Mat& mask = {});

/// The features of `rows` (indices into f, in that order).
Features select_features(const Features& f, const std::vector<int>& rows);

/// Reads an image file (8-bit, colour or grey). Throws Error naming the file when it cannot be
/// read or decoded.
cv::Mat read_image(const std::filesystem::path& path);

/// The features of an image file: extract_features of its pixels (grey when `grey`, else BGR),
/// within its alpha channel when options.alpha_mask. Errors name the file.
Features extract_file_features(const std::filesystem::path& path, const ExtractOptions& options,
                               bool grey = false);

/// The same on `image`, already decoded from `path` (which names errors and, with
/// options.alpha_mask, gives the alpha channel): for a caller that needs the pixels too.
Features extract_file_features(const std::filesystem::path& path, const cv::Mat& image,
                               const ExtractOptions& options);

/// An image file's alpha channel as a mask (CV_8U, 255 where alpha is non-zero). Throws Error
/// naming the file when it cannot be read or has no alpha channel (not 4 channels).
cv::Mat read_alpha_mask(const std::filesystem::path& path);

}  // namespace proprio::features
