// Uses the installed headers and libraries: projects a point and prints the proprio version.
#include <cstdio>

#include "proprio/core/version.hpp"
#include "proprio/geometry/camera.hpp"

int main() {
  proprio::geometry::Camera cam;
  cam.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  cam.t << 0, 0, 2;
  const Eigen::Vector2d x = cam.project(Eigen::Vector3d(0.2, -0.1, 0.0));
  std::printf("proprio %s projects to %.1f %.1f\n", proprio::kVersion, x.x(), x.y());
  return (x - Eigen::Vector2d(370, 215)).norm() < 1e-9 ? 0 : 1;
}
