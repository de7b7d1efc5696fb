#include "proprio/features/image_set.hpp"

#include <algorithm>
#include <cctype>

#include "proprio/core/error.hpp"

namespace proprio::features {
namespace fs = std::filesystem;

namespace {

bool is_image(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" ||
         ext == ".tiff" || ext == ".ppm" || ext == ".pgm";
}

bool hidden(const fs::path& p) {
  const auto name = p.filename().string();
  return !name.empty() && name[0] == '.';
}

}  // namespace

ImageSet read_image_set(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error::in_file(dir, "not a directory of image classes");
  std::vector<fs::path> class_dirs;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!hidden(e.path()) && e.is_directory()) class_dirs.push_back(e.path());
  }
  std::sort(class_dirs.begin(), class_dirs.end());
  ImageSet set;
  for (const auto& cdir : class_dirs) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(cdir)) {
      if (!hidden(e.path()) && e.is_regular_file() && is_image(e.path())) {
        files.push_back(e.path());
      }
    }
    if (files.empty()) continue;
    std::sort(files.begin(), files.end());
    const int label = static_cast<int>(set.classes.size());
    set.classes.push_back(cdir.filename().string());
    for (auto& f : files) {
      set.images.push_back(std::move(f));
      set.labels.push_back(label);
    }
  }
  if (set.images.empty()) {
    throw Error::in_file(dir, "no images (expected DIR/<class>/<image>.png|jpg|...)");
  }
  return set;
}

}  // namespace proprio::features
