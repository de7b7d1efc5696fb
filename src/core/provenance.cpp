#include "proprio/core/provenance.hpp"

#include <chrono>
#include <ctime>

#include "proprio/core/version.hpp"

namespace proprio::core {
namespace {

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

Provenance Provenance::current(const std::vector<std::string>& argv,
                               std::optional<std::uint64_t> seed) {
  Provenance p;
  p.proprio_version = kVersion;
  p.git_commit = kGitCommit;
  for (const auto& a : argv) p.command_line += (p.command_line.empty() ? "" : " ") + a;
  p.seed = seed;
  p.created_utc = utc_now();
  return p;
}

Provenance Provenance::current(int argc, const char* const* argv,
                               std::optional<std::uint64_t> seed) {
  return current(std::vector<std::string>(argv, argv + argc), seed);
}

Json to_json(const Provenance& p) {
  Json j = {{"proprio_version", p.proprio_version}, {"git_commit", p.git_commit},
            {"command_line", p.command_line},       {"opencv_version", p.opencv_version},
            {"mujoco_version", p.mujoco_version},   {"created_utc", p.created_utc}};
  j["seed"] = p.seed ? Json(*p.seed) : Json(nullptr);
  return j;
}

Provenance provenance_from_json(const Json& j, const std::string& file) {
  Provenance p;
  p.proprio_version = json_get<std::string>(j, "proprio_version", file);
  p.git_commit = json_get<std::string>(j, "git_commit", file);
  p.command_line = json_get<std::string>(j, "command_line", file);
  p.opencv_version = json_get<std::string>(j, "opencv_version", file);
  p.mujoco_version = json_get<std::string>(j, "mujoco_version", file);
  p.created_utc = json_get<std::string>(j, "created_utc", file);
  if (j.contains("seed") && !j["seed"].is_null()) p.seed = json_get<std::uint64_t>(j, "seed", file);
  return p;
}

Json result_document(const std::string& format, int format_version, const Provenance& p) {
  return Json{{"format", format}, {"format_version", format_version}, {"provenance", to_json(p)}};
}

}  // namespace proprio::core
