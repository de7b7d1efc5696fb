#include "proprio/episode/summary.hpp"

#include <cstdio>

namespace proprio::episode {

EpisodeSummary summarize(const Episode& e) {
  const EpisodeInfo& info = e.info();
  EpisodeSummary s;
  s.dir = e.dir().string();
  s.frames = info.frame_count;
  s.fps = info.fps;
  s.duration = info.duration();
  s.first_time = e.arm().front().t;
  s.last_time = e.arm().back().t;
  s.width = info.width;
  s.height = info.height;
  s.arm = info.arm_name;
  s.joints = info.joint_count;
  s.source = info.provenance.source;
  s.seed = info.provenance.run.seed;
  s.scenario = info.provenance.scenario;
  s.switches = info.provenance.switches;
  s.target = info.target;
  if (info.target) {
    if (const ObjectInfo* o = e.object(*info.target)) s.target_name = o->name;
  }
  s.objects = e.objects();
  s.first_touch_frame = e.first_touch_frame();
  for (const auto& a : e.arm()) s.touching_frames += a.touching ? 1 : 0;
  s.storage = info.storage;
  s.masks = info.has_masks;
  s.depth = info.has_depth;
  s.stereo = info.stereo;
  return s;
}

std::vector<EpisodeObjectRecord> EpisodeSummary::object_records(
    const std::vector<ObjectInfo>& objects) {
  std::vector<EpisodeObjectRecord> out;
  out.reserve(objects.size());
  for (const auto& o : objects) out.push_back({o.id, o.name, to_string(o.role)});
  return out;
}

std::string EpisodeInfoResult::brief() const { return format_summary(summary); }

EpisodeInfoResult run_episode_info(const std::filesystem::path& dir,
                                   const core::Provenance& provenance) {
  EpisodeInfoResult r;
  r.summary = summarize(read_episode(dir));
  r.message = r.summary.dir + ": " + std::to_string(r.summary.frames) + " frames, " +
              r.summary.scenario.value_or("no scenario");
  r.document = core::result_document("proprio.episode.info", 1, provenance);
  core::fields_into_json(r.summary, r.document);
  return r;
}

std::string format_summary(const EpisodeSummary& s) {
  char buf[256];
  std::string out;
  const auto line = [&out](const std::string& key, const std::string& value) {
    out += key;
    out += ": ";
    out += value;
    out += '\n';
  };
  line("episode", s.dir);
  std::snprintf(buf, sizeof buf, "%d at %g fps, %.3f s (t = %.3f .. %.3f s)", s.frames, s.fps,
                s.duration, s.first_time, s.last_time);
  line("frames", buf);
  line("image", std::to_string(s.width) + "x" + std::to_string(s.height) + " (" +
                    to_string(s.storage) + ")");
  line("arm", s.arm + " (" + std::to_string(s.joints) + " joints)");
  std::string source = to_string(s.source);
  if (s.seed) source += ", seed " + std::to_string(*s.seed);
  line("source", source);
  std::string scenario = s.scenario ? *s.scenario : "none";
  if (!s.switches.empty()) {
    scenario += ' ';
    scenario += s.switches.dump();
  }
  line("scenario", scenario);
  std::string target = "none";
  if (s.target) {
    target = std::to_string(*s.target);
    if (s.target_name) target += " (" + *s.target_name + ")";
  }
  line("target", target);
  std::string objects;
  for (const auto& o : s.objects) {
    if (!objects.empty()) objects += ", ";
    objects += std::to_string(o.id) + " " + o.name + " (" + to_string(o.role) + ")";
  }
  line("objects", objects.empty() ? "none" : objects);
  line("first touch", s.first_touch_frame
                          ? "frame " + std::to_string(*s.first_touch_frame) + " (" +
                                std::to_string(s.touching_frames) + " touching frames)"
                          : std::string("never"));
  const auto yes = [](bool b) { return std::string(b ? "yes" : "no"); };
  line("masks", yes(s.masks));
  line("depth", yes(s.depth));
  line("stereo", yes(s.stereo));
  return out;
}

}  // namespace proprio::episode
