#pragma once
// Folder-per-class image sets (Caltech-256's layout: DIR/<class>/<image>), as used to build a
// "universal" dictionary (thesis 6.3.1) and to classify images.

#include <filesystem>
#include <string>
#include <vector>

namespace proprio::features {

struct ImageSet {
  std::vector<std::string> classes;           ///< sub-folder names, sorted
  std::vector<std::filesystem::path> images;  ///< sorted by class, then file name
  std::vector<int> labels;                    ///< index into classes of every image
};

/// Lists the images (.png .jpg .jpeg .bmp .tif .tiff .ppm .pgm, any case) in every sub-folder of
/// `dir`. Hidden entries are skipped; classes without images are left out. Throws Error when
/// `dir` is not a directory or holds no images.
ImageSet read_image_set(const std::filesystem::path& dir);

}  // namespace proprio::features
