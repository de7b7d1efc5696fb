#include "camera_shake.hpp"
#include "proprio/core/random.hpp"

#include <Eigen/Geometry>

namespace proprio::sim {

namespace {

// Largest offset per axis, m, and turn, rad (about 0.4 degrees): a tremble, not a new view.
constexpr double kMaxOffset = 0.004;
constexpr double kMaxTurn = 0.007;
// The shake's stream: the seed xor "SHAKE".
constexpr std::uint64_t kShakeStream = 0x5348414b45ULL;

}  // namespace

CameraShake::CameraShake(const World& world, std::uint64_t seed)
    : rng_(core::stream_seed(seed, kShakeStream)) {
  for (const auto& n : world.camera_names()) camera_ids_.push_back(world.camera_id(n));
}

void CameraShake::apply(World& world) {
  mjData& d = world.data();
  const Eigen::Vector3d dp(rng_.uniform(-kMaxOffset, kMaxOffset),
                           rng_.uniform(-kMaxOffset, kMaxOffset),
                           rng_.uniform(-kMaxOffset, kMaxOffset));
  const Eigen::Vector3d axis(rng_.normal(), rng_.normal(), rng_.normal());
  const double angle = rng_.uniform(-kMaxTurn, kMaxTurn);
  const Eigen::Matrix3d dr = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  for (int id : camera_ids_) {
    Eigen::Map<Eigen::Vector3d> pos(d.cam_xpos + 3 * id);
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(d.cam_xmat + 9 * id);
    pos += dp;
    rot = (dr * rot).eval();
  }
}

}  // namespace proprio::sim
