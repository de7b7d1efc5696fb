#include <algorithm>
#include <charconv>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "layout.hpp"
#include "parse.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/image_header.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/geometry/image_file.hpp"

namespace proprio::episode {

std::filesystem::path image_path(const std::filesystem::path& episode_dir,
                                 const std::string& subdir, int i) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", i);
  return episode_dir / subdir / name;
}

namespace detail {
namespace fs = std::filesystem;

std::vector<int> unknown_mask_ids(const cv::Mat& mask, const std::vector<ObjectInfo>& objects) {
  std::vector<bool> seen(65536, false);
  for (int r = 0; r < mask.rows; ++r) {
    const auto* p = mask.ptr<std::uint16_t>(r);
    for (int c = 0; c < mask.cols; ++c) seen[p[c]] = true;
  }
  seen[0] = false;
  for (const auto& o : objects) seen[static_cast<size_t>(o.id)] = false;
  std::vector<int> out;
  for (int id = 1; id < 65536; ++id) {
    if (seen[static_cast<size_t>(id)]) out.push_back(id);
  }
  return out;
}

std::string list_ids(const std::vector<int>& ids) {
  std::string s;
  for (size_t k = 0; k < ids.size() && k < 10; ++k) {
    if (k > 0) s += ", ";
    s += std::to_string(ids[k]);
  }
  if (ids.size() > 10) s += ", ...";
  return s;
}

namespace {

enum class ImageKind { kFrame, kMask, kDepth };

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

/// Index of a file named like 000012.png, or none.
std::optional<long> numbered_png(const std::string& name) {
  if (name.size() < 10 || name.compare(name.size() - 4, 4, ".png") != 0) return std::nullopt;
  const size_t digits = name.size() - 4;
  if (digits < 6) return std::nullopt;
  long v = 0;
  const auto [ptr, ec] = std::from_chars(name.data(), name.data() + digits, v);
  if (ec != std::errc() || ptr != name.data() + digits) return std::nullopt;
  return v;
}

void check_png_set(const fs::path& dir, const std::string& subdir, const EpisodeInfo& info,
                   ImageKind kind, const Loaded& loaded, bool decode, ProblemSink& sink) {
  const fs::path folder = dir / subdir;
  const std::string group = folder.string();
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    sink.add(folder, "missing directory (episode.json declares " +
                         std::to_string(info.frame_count) + " frames)");
    return;
  }
  std::vector<bool> present(static_cast<size_t>(info.frame_count), false);
  long beyond = 0;
  long first_beyond = -1;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const auto index = numbered_png(entry.path().filename().string());
    if (!index) continue;
    if (*index < info.frame_count) {
      present[static_cast<size_t>(*index)] = true;
    } else {
      ++beyond;
      if (first_beyond < 0 || *index < first_beyond) first_beyond = *index;
    }
  }
  if (beyond > 0) {
    sink.add(folder,
             "holds " + std::to_string(beyond) + " image" + (beyond == 1 ? "" : "s") +
                 " beyond episode.json's frame_count " + std::to_string(info.frame_count) +
                 " (the first is " +
                 image_path(dir, subdir, static_cast<int>(first_beyond)).filename().string() + ")");
  }
  const bool ids = kind == ImageKind::kMask;
  for (int i = 0; i < info.frame_count; ++i) {
    const fs::path file = image_path(dir, subdir, i);
    if (!present[static_cast<size_t>(i)]) {
      sink.add(file,
               "missing (episode.json declares " + std::to_string(info.frame_count) + " frames)", 0,
               group);
      continue;
    }
    std::string why;
    const auto header = core::probe_image_header(file, why);
    if (!header) {
      sink.add(file, why, 0, group);
      continue;
    }
    if (header->format != core::ImageFormat::kPng) {
      sink.add(file, "is a " + core::describe(*header) + ", episode images must be PNG", 0, group);
      continue;
    }
    if (header->width != info.width || header->height != info.height) {
      sink.add(file,
               "is " + size_str(header->width, header->height) + ", expected " +
                   size_str(info.width, info.height) + " (episode.json's image size)",
               0, group);
      continue;
    }
    if (kind == ImageKind::kFrame && header->bit_depth != 8) {
      sink.add(file, "is " + core::describe(*header) + ", frames must be 8-bit", 0, group);
      continue;
    }
    if (kind != ImageKind::kFrame &&
        (header->bit_depth != 16 || header->channels != 1 || header->palette)) {
      sink.add(file,
               "is " + core::describe(*header) + ", " + (ids ? "masks" : "depth images") +
                   " must be 16-bit grey",
               0, group);
      continue;
    }
    if (!decode) continue;
    cv::Mat image;
    try {
      image = geometry::read_image(
          file, kind == ImageKind::kFrame ? cv::IMREAD_COLOR : cv::IMREAD_UNCHANGED);
    } catch (const Error&) {
      sink.add(file, "cannot be decoded (corrupt PNG data)", 0, group);
      continue;
    }
    if (ids && loaded.objects_valid) {
      const auto unknown = unknown_mask_ids(image, loaded.objects);
      if (!unknown.empty()) {
        sink.add(file,
                 "holds object id" + std::string(unknown.size() == 1 ? " " : "s ") +
                     list_ids(unknown) + " that objects.json lacks",
                 0, group);
      }
    }
  }
}

void check_video(const fs::path& file, const EpisodeInfo& info, bool decode, ProblemSink& sink) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    sink.add(file, "missing (episode.json names it as the video of the frames)");
    return;
  }
  cv::VideoCapture cap;
  if (!cap.open(file.string()) || !cap.isOpened()) {
    sink.add(file, "cannot open as a video (OpenCV cannot read it)");
    return;
  }
  const int w = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_WIDTH));
  const int h = static_cast<int>(cap.get(cv::CAP_PROP_FRAME_HEIGHT));
  if (w > 0 && h > 0 && (w != info.width || h != info.height)) {
    sink.add(file, "frames are " + size_str(w, h) + ", expected " +
                       size_str(info.width, info.height) + " (episode.json's image size)");
    return;
  }
  if (!decode) {
    const double n = cap.get(cv::CAP_PROP_FRAME_COUNT);
    if (n > 0 && static_cast<long>(n) != info.frame_count) {
      sink.add(file, "reports " + std::to_string(static_cast<long>(n)) +
                         " frames, episode.json says frame_count " +
                         std::to_string(info.frame_count));
    }
    return;
  }
  cv::Mat frame;
  long count = 0;
  bool size_reported = false;
  while (cap.read(frame) && !frame.empty()) {
    if (!size_reported && (frame.cols != info.width || frame.rows != info.height)) {
      sink.add(file, "frame " + std::to_string(count) + " is " + size_str(frame.cols, frame.rows) +
                         ", expected " + size_str(info.width, info.height));
      size_reported = true;
    }
    ++count;
  }
  if (count != info.frame_count) {
    sink.add(file, "holds " + std::to_string(count) +
                       " decodable frames, episode.json says "
                       "frame_count " +
                       std::to_string(info.frame_count));
  }
}

std::optional<geometry::Camera> load_camera(const fs::path& file, const EpisodeInfo* info,
                                            ProblemSink& sink) {
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    sink.add(file, "missing (the episode's camera calibration)");
    return std::nullopt;
  }
  geometry::Camera cam;
  try {
    cam = geometry::read_calib(file);
  } catch (const Error& e) {
    sink.add_error(file, e);
    return std::nullopt;
  }
  if (info) {
    if (cam.width > 0 && (cam.width != info->width || cam.height != info->height)) {
      sink.add(file, "is for " + size_str(cam.width, cam.height) +
                         " images, episode.json's image size is " +
                         size_str(info->width, info->height));
      return std::nullopt;
    }
    cam.width = info->width;
    cam.height = info->height;
  }
  return cam;
}

/// A directory or file the episode has but episode.json does not declare.
void check_undeclared(const fs::path& path, bool declared, const std::string& flag,
                      ProblemSink& sink) {
  std::error_code ec;
  if (!declared && fs::exists(path, ec)) {
    sink.add(path, "exists, but episode.json says " + flag + ": false");
  }
}

}  // namespace

Loaded load_episode(const fs::path& dir, ProblemSink& sink, const CheckOptions& options) {
  Loaded out;
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    sink.add(dir, "no such episode directory");
    return out;
  }
  if (!fs::is_directory(dir, ec)) {
    sink.add(dir, "is not a directory (an episode is a directory)");
    return out;
  }

  const fs::path info_file = dir / kEpisodeJson;
  if (!fs::exists(info_file, ec)) {
    sink.add(info_file, "missing (every episode has one)");
  } else {
    try {
      out.info = parse_episode_info(core::read_json(info_file), info_file, sink);
    } catch (const Error& e) {
      sink.add_error(info_file, e);
    }
  }
  const EpisodeInfo* info = out.info ? &*out.info : nullptr;

  out.camera = load_camera(dir / kCalib, info, sink);
  if (info && info->stereo) out.right_camera = load_camera(dir / kCalibRight, info, sink);

  const fs::path objects_file = dir / kObjectsJson;
  if (fs::exists(objects_file, ec)) {
    try {
      if (auto objects = parse_objects(core::read_json(objects_file), objects_file, sink)) {
        out.objects = std::move(*objects);
        out.objects_valid = true;
      }
    } catch (const Error& e) {
      sink.add_error(objects_file, e);
    }
  } else if (info && (info->has_masks || info->target)) {
    sink.add(objects_file, std::string("missing; episode.json ") +
                               (info->has_masks ? "declares masks" : "names a target") +
                               ", whose ids objects.json defines");
  }
  if (info && out.objects_valid) {
    const auto target = std::find_if(out.objects.begin(), out.objects.end(),
                                     [](const auto& o) { return o.role == ObjectRole::kTarget; });
    if (info->target) {
      const auto it = std::find_if(out.objects.begin(), out.objects.end(),
                                   [&](const auto& o) { return o.id == *info->target; });
      if (it == out.objects.end()) {
        sink.add(objects_file, "lacks episode.json's target " + std::to_string(*info->target));
      } else if (it->role != ObjectRole::kTarget) {
        sink.add(objects_file, "object " + std::to_string(it->id) + " is episode.json's target " +
                                   "but has the role '" + to_string(it->role) + "'");
      }
    } else if (target != out.objects.end()) {
      sink.add(objects_file, "object " + std::to_string(target->id) +
                                 " has the role 'target', but episode.json's target is null");
    }
  }

  const fs::path arm_file = dir / kArmCsv;
  if (!fs::exists(arm_file, ec)) {
    sink.add(arm_file, "missing (the arm's state at every frame)");
  } else {
    try {
      int rows = 0;
      out.arm =
          parse_arm_csv(core::read_file(arm_file), arm_file,
                        info ? std::optional<int>(info->joint_count) : std::nullopt, sink, rows);
      if (info && rows > 0 && rows != info->frame_count) {
        sink.add(arm_file, "has " + std::to_string(rows) + " rows, episode.json says frame_count " +
                               std::to_string(info->frame_count));
        out.arm.reset();
      }
    } catch (const Error& e) {
      sink.add_error(arm_file, e);
    }
  }

  if (!info) return out;  // without episode.json nothing says what the images should be
  const bool decode = options.decode_images;
  if (info->storage == FrameStorage::kPng) {
    check_png_set(dir, kFramesDir, *info, ImageKind::kFrame, out, decode, sink);
    if (info->stereo)
      check_png_set(dir, kFramesRightDir, *info, ImageKind::kFrame, out, decode, sink);
  } else {
    check_video(dir / info->video_file, *info, decode, sink);
    if (info->stereo) check_video(dir / info->video_file_right, *info, decode, sink);
  }
  check_undeclared(dir / kCalibRight, info->stereo, "stereo", sink);
  check_undeclared(dir / kFramesRightDir, info->stereo, "stereo", sink);
  if (info->has_masks) {
    check_png_set(dir, kMasksDir, *info, ImageKind::kMask, out, decode, sink);
  } else {
    check_undeclared(dir / kMasksDir, false, "masks", sink);
  }
  if (info->has_depth) {
    check_png_set(dir, kDepthDir, *info, ImageKind::kDepth, out, decode, sink);
  } else {
    check_undeclared(dir / kDepthDir, false, "depth", sink);
  }
  return out;
}

}  // namespace detail

std::vector<Problem> check_episode(const std::filesystem::path& dir, const CheckOptions& options) {
  detail::ProblemSink sink(false, std::max(1, options.max_problems_per_file));
  detail::load_episode(dir, sink, options);
  return sink.take();
}

std::string CheckResult::brief() const {
  if (problems.empty()) return message + "\n";
  std::string out;
  for (const auto& p : problems) out += p.message + "\n";
  return out;
}

CheckResult run_episode_check(const std::filesystem::path& dir, const CheckOptions& options,
                              const core::Provenance& provenance) {
  CheckResult r;
  r.dir = dir;
  r.decoded_images = options.decode_images;
  r.problems = check_episode(dir, options);
  r.message = dir.string();
  if (r.problems.empty()) {
    r.message += ": valid episode";
  } else {
    r.message += ": not a valid episode (" + std::to_string(r.problems.size()) +
                 (r.problems.size() == 1 ? " problem)" : " problems)");
  }
  r.document = core::result_document("proprio.episode.check", 1, provenance);
  core::fields_into_json(r, r.document);
  return r;
}

}  // namespace proprio::episode
