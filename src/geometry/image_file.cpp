#include "proprio/geometry/image_file.hpp"

#include "proprio/core/error.hpp"
#include "proprio/core/image_header.hpp"
#include "proprio/core/stderr_capture.hpp"

namespace proprio::geometry {

cv::Mat read_image(const std::filesystem::path& path, int flags) {
  const core::ImageHeader header = core::read_image_header(path);
  cv::Mat image;
  {
    // libjpeg and libpng print warnings of their own ("Premature end of JPEG file"); they go to
    // the debug log, not to the user's terminal.
    const core::StderrCapture quiet("image decoder");
    image = cv::imread(path.string(), flags);
  }
  if (image.empty()) {
    throw Error::in_file(path, "cannot decode the " + core::describe(header) + " (corrupt data)");
  }
  return image;
}

}  // namespace proprio::geometry
