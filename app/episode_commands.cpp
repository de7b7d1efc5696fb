// proprio episode ...: the recorded-interaction format (docs/formats/episode.md).
#include <cstdio>
#include <memory>

#include "cli.hpp"
#include "proprio/core/error.hpp"
#include "proprio/episode/check.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/episode/import.hpp"
#include "proprio/episode/summary.hpp"

namespace proprio::app {
namespace {

struct InfoArgs {
  std::string dir;
  JsonFlag json;
};

struct CheckArgs {
  std::string dir;
  JsonFlag json;
  bool quick = false;
};

struct ImportArgs {
  std::string video;
  std::string arm_log;
  std::string calib;
  std::string out;
  JsonFlag json;
  std::string frames = "png";
  std::optional<double> fps;
  std::optional<int> max_frames;
  std::string scenario;
  bool quiet = false;
  episode::ImportOptions options;
};

void run_info(const InfoArgs& a, const Invocation& inv) {
  a.json.refuse({a.dir});
  const episode::EpisodeInfoResult r = episode::run_episode_info(a.dir, inv.provenance());
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
}

void run_check(const CheckArgs& a, const Invocation& inv) {
  episode::CheckOptions options;
  options.decode_images = !a.quick;
  a.json.refuse({a.dir});
  const auto r = episode::run_episode_check(a.dir, options, inv.provenance());
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
  if (!r.valid()) throw Error(r.message);
}

void run_import(ImportArgs a, const Invocation& inv) {
  a.options.fps = a.fps;
  a.options.max_frames = a.max_frames;
  if (!a.scenario.empty()) a.options.scenario = a.scenario;
  a.options.storage =
      a.frames == "video" ? episode::FrameStorage::kVideo : episode::FrameStorage::kPng;
  a.options.progress = !a.quiet;
  a.json.refuse({a.video, a.arm_log, a.calib, a.out});
  const core::Provenance provenance = inv.provenance();
  const auto result =
      episode::import_recording(a.video, a.arm_log, a.calib, a.out, a.options, provenance);
  std::fputs(result.brief().c_str(), stdout);
  a.json.write(result.document);
}

}  // namespace

void register_episode_commands(CLI::App& root, const Invocation& inv) {
  auto* episode = root.add_subcommand("episode", "Inspect, check and import episodes");
  episode->require_subcommand(1);

  auto info_args = std::make_shared<InfoArgs>();
  auto* info =
      episode->add_subcommand("info", "Summarise an episode (reads it with every cheap check)");
  info->add_option("DIR", info_args->dir, "Episode directory")->required();
  info_args->json.add_to(info, "the summary");
  info->callback([info_args, &inv] { run_info(*info_args, inv); });

  auto check_args = std::make_shared<CheckArgs>();
  auto* check = episode->add_subcommand(
      "check", "Validate an episode: print every problem; exit 0 when valid, 2 when not");
  check->add_option("DIR", check_args->dir, "Episode directory")->required();
  check->add_flag("--quick", check_args->quick,
                  "Skip decoding the images (headers, sizes and files only)");
  check_args->json.add_to(check, "the problems");
  check->callback([check_args, &inv] { run_check(*check_args, inv); });

  auto import_args = std::make_shared<ImportArgs>();
  auto* imp = episode->add_subcommand(
      "import", "Turn a real recording (video, timestamped arm log, calibration) into an episode");
  imp->add_option("--video", import_args->video, "Video file OpenCV can read")->required();
  imp->add_option("--arm-log", import_args->arm_log,
                  "CSV with t (s), ee_x,ee_y,ee_z (m), optional q1..qN (rad), touching (0/1)")
      ->required();
  imp->add_option("--calib", import_args->calib, "calib.yml of the camera (OpenCV YAML)")
      ->required();
  imp->add_option("--out", import_args->out, "Episode directory to create")->required();
  imp->add_option("--fps", import_args->fps, "Frame rate of the video (default: what it states)");
  imp->add_option("--time-offset", import_args->options.time_offset,
                  "Log time of the video's first frame, s: frame i is at offset + i/fps")
      ->capture_default_str();
  imp->add_option("--max-frames", import_args->max_frames, "Write at most this many frames");
  imp->add_option("--arm", import_args->options.arm_name, "Name of the arm")->capture_default_str();
  imp->add_option("--scenario", import_args->scenario, "Name of what the recording shows");
  imp->add_option("--frames", import_args->frames, "Store frames as png or video")
      ->check(CLI::IsMember({"png", "video"}))
      ->capture_default_str();
  imp->add_flag("--overwrite,--force", import_args->options.overwrite,
                "Replace an existing episode at --out (--force: the older name)");
  imp->add_flag("-q,--quiet", import_args->quiet, "No progress bar");
  import_args->json.add_to(imp, "the import summary");
  imp->callback([import_args, &inv] { run_import(*import_args, inv); });
}

}  // namespace proprio::app
