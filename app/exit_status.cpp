#include "exit_status.hpp"

#include <cstdio>
#include <exception>
#include <opencv2/core.hpp>

#include "proprio/core/error.hpp"

namespace proprio::app {

int run_with_exit_status(const std::function<int()>& body) {
  try {
    return body();
  } catch (const Error& e) {
    std::fprintf(stderr, "proprio: %s\n", e.what());
    return 2;
  } catch (const InternalError& e) {
    std::fprintf(stderr, "proprio: internal error: %s\n", e.what());
    return 1;
  } catch (const cv::Exception& e) {
    std::fprintf(stderr, "proprio: internal error in OpenCV: %s\n", e.err.c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "proprio: internal error: %s\n", e.what());
    return 1;
  }
}

}  // namespace proprio::app
