#include "proprio/sim/views.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/random.hpp"
#include "proprio/geometry/image_file.hpp"
#include "proprio/sim/renderer.hpp"
#include "proprio/sim/world.hpp"

namespace proprio::sim {
namespace fs = std::filesystem;

std::vector<fs::path> ViewsOptions::default_backgrounds() {
  const fs::path d = ObjectCatalogue::default_texture_dir();
  std::vector<fs::path> v;
  for (const char* n :
       {"building.jpg", "home.jpg", "fruits.jpg", "baboon.jpg", "aero1.jpg", "butterfly.jpg",
        "lena.jpg", "graf1.png", "box_in_scene.png", "leuvenA.jpg"}) {
    if (fs::exists(d / n)) v.push_back(d / n);
  }
  return v;
}

void ViewsOptions::validate() const {
  require(!objects.empty(), "views: no objects");
  require(per_object >= 1 && per_object <= 100000, "views: per-object must be 1..100000");
  require(width >= 16 && height >= 16 && width <= 4096 && height <= 4096,
          "views: image size must be 16..4096 pixels per side");
  require(!backgrounds.empty(), "views: no background photographs");
  require(0.1 <= min_distance && min_distance <= max_distance && max_distance < 3.0,
          "views: distances must satisfy 0.1 <= min <= max < 3 m");
  require(
      0 <= min_elevation_deg && min_elevation_deg <= max_elevation_deg && max_elevation_deg < 90,
      "views: elevations must satisfy 0 <= min <= max < 90 degrees");
}

ViewsSummary render_views(const fs::path& out, const ViewsOptions& options,
                          const ObjectCatalogue& catalogue) {
  options.validate();
  for (const auto& o : options.objects) (void)catalogue.get(o);  // unknown names fail first
  core::require_output_not_input(out, options.backgrounds, "--out");
  std::vector<cv::Mat> photos;
  for (const auto& p : options.backgrounds) {
    photos.push_back(geometry::read_image(p, cv::IMREAD_COLOR));
  }
  core::StagedDirectory staged(out);
  core::Rng rng(options.seed);
  ViewsSummary summary;
  for (const auto& name : options.objects) {
    SceneDescription d = default_scene();
    d.arm_model.clear();
    d.cameras.at(0).width = options.width;
    d.cameras.at(0).height = options.height;
    PlacedObject o;
    o.type = name;
    o.position = {0.35, 0.1};
    d.objects.push_back(o);
    d.backdrop.center = {0.35, 0.45, 0.3};
    d.backdrop.size = {1.6, 1.2};
    World world = World::build(d, catalogue);
    Renderer renderer(world, RenderOptions{.shadows = false, .reflections = false});
    const std::string cam = world.camera_names().at(0);
    const int cam_id = world.camera_id(cam);
    const ObjectId id = world.objects().at(0).id;
    const ObjectType& type = world.objects().at(0).type;
    const fs::path dir = staged.staging_path() / name;
    fs::create_directories(dir);
    for (int k = 0; k < options.per_object; ++k) {
      Pose pose = Pose::Identity();
      pose.linear() = Eigen::AngleAxisd(rng.uniform(-std::numbers::pi, std::numbers::pi),
                                        Eigen::Vector3d::UnitZ())
                          .toRotationMatrix();
      pose.translation() = Eigen::Vector3d(0.35, 0.1, type.bottom());
      world.set_object_pose(id, pose);
      world.set_texture_image(kBackdropTexture,
                              photos[static_cast<std::size_t>(rng.index(photos.size()))]);
      renderer.upload_texture(world, kBackdropTexture);
      // Camera in the front half (the backdrop stays behind the object), looking at its centre.
      const double az = rng.uniform(-0.8, 0.8) - std::numbers::pi / 2;
      const double el = rng.uniform(options.min_elevation_deg, options.max_elevation_deg) *
                        std::numbers::pi / 180.0;
      const double dist = rng.uniform(options.min_distance, options.max_distance);
      const Eigen::Vector3d target = pose.translation() + Eigen::Vector3d(0, 0, type.center().z());
      const Eigen::Vector3d eye =
          target + dist * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                          std::sin(el));
      const Eigen::Vector3d fwd = (target - eye).normalized();
      const Eigen::Vector3d right = fwd.cross(Eigen::Vector3d::UnitZ()).normalized();
      const Eigen::Vector3d up = right.cross(fwd);
      // MuJoCo's camera frame: x right, y up, looking along -z; cam_xmat is row-major with the
      // frame's axes as columns. Overrides the derived pose until the next mj_forward.
      mjData& data = world.data();
      for (int i = 0; i < 3; ++i) {
        data.cam_xpos[3 * cam_id + i] = eye[i];
        data.cam_xmat[9 * cam_id + 3 * i + 0] = right[i];
        data.cam_xmat[9 * cam_id + 3 * i + 1] = up[i];
        data.cam_xmat[9 * cam_id + 3 * i + 2] = -fwd[i];
      }
      cv::Mat rgb = renderer.rgb(world, cam);
      if (options.masks) {
        // BGRA: the colours, and alpha 255 exactly where the object's id is in the mask.
        const cv::Mat ids = renderer.mask(world, cam);
        const cv::Mat alpha = ids == static_cast<int>(id);
        cv::Mat bgra;
        cv::merge(std::vector<cv::Mat>{rgb, alpha}, bgra);  // planes of one depth, any channels
        rgb = bgra;
      }
      char file[32];
      std::snprintf(file, sizeof file, "%06d.png", k);
      if (!cv::imwrite((dir / file).string(), rgb)) {
        throw Error::in_file(dir / file, "cannot write the image");
      }
      ++summary.images;
    }
  }
  staged.commit();
  summary.message = std::to_string(summary.images) + " images of " +
                    std::to_string(options.objects.size()) + " objects";
  return summary;
}

}  // namespace proprio::sim
