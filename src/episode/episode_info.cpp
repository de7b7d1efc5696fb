#include "proprio/episode/episode_info.hpp"

#include <cmath>

#include "parse.hpp"

namespace proprio::episode {

std::string to_string(Source s) { return s == Source::kSimulated ? "simulated" : "real"; }
std::string to_string(FrameStorage s) { return s == FrameStorage::kPng ? "png" : "video"; }

core::Json to_json(const EpisodeInfo& info) {
  core::Json j = core::result_document(kEpisodeFormat, info.format_version, info.provenance.run);
  auto& prov = j["provenance"];
  prov["source"] = to_string(info.provenance.source);
  prov["scenario"] = info.provenance.scenario ? core::Json(*info.provenance.scenario) : nullptr;
  prov["switches"] = info.provenance.switches;
  j["frame_count"] = info.frame_count;
  j["fps"] = info.fps;
  j["image"] = {{"width", info.width}, {"height", info.height}};
  j["arm"] = {{"name", info.arm_name}, {"joints", info.joint_count}};
  core::Json frames = {{"storage", to_string(info.storage)}};
  if (info.storage == FrameStorage::kVideo) {
    frames["file"] = info.video_file;
    if (info.stereo) frames["file_right"] = info.video_file_right;
  }
  j["frames"] = frames;
  j["masks"] = info.has_masks;
  j["depth"] = info.has_depth;
  j["stereo"] = info.stereo;
  j["target"] = info.target ? core::Json(*info.target) : nullptr;
  return j;
}

EpisodeInfo episode_info_from_json(const core::Json& j, const std::filesystem::path& file) {
  detail::ProblemSink sink(true, 1);
  auto info = detail::parse_episode_info(j, file, sink);
  // The sink throws on the first problem, so a parse without a result is a bug here.
  ensure(info.has_value(), file.string() + ": episode.json parsed to nothing without a problem");
  return *info;
}

namespace detail {
namespace {

/// Typed access to the keys of one JSON object, reporting each problem once.
class Fields {
 public:
  Fields(const core::Json& j, const std::filesystem::path& file, ProblemSink& sink,
         std::string prefix = {})
      : j_(j), file_(file), sink_(sink), prefix_(std::move(prefix)) {}

  const core::Json* find(const std::string& key, bool required = true) {
    const auto it = j_.find(key);
    if (it == j_.end()) {
      if (required) fail("missing key '" + prefix_ + key + "'");
      return nullptr;
    }
    return &*it;
  }

  std::optional<long long> integer(const std::string& key, long long lo, long long hi) {
    const core::Json* v = find(key);
    if (!v) return std::nullopt;
    if (!v->is_number_integer()) return wrong_type(key, *v, "an integer");
    if (v->is_number_unsigned() &&
        v->get<unsigned long long>() > static_cast<unsigned long long>(hi)) {
      return out_of_range(key, *v, lo, hi);
    }
    const long long x = v->get<long long>();
    if (x < lo || x > hi) return out_of_range(key, *v, lo, hi);
    return x;
  }

  std::optional<double> number(const std::string& key, double lo_exclusive, double hi) {
    const core::Json* v = find(key);
    if (!v) return std::nullopt;
    if (!v->is_number()) {
      wrong_type(key, *v, "a number");
      return std::nullopt;
    }
    const double x = v->get<double>();
    if (!std::isfinite(x) || x <= lo_exclusive || x > hi) {
      std::string m = "'" + prefix_ + key + "' is ";
      m += v->dump();
      m += ", expected a number in (" + format(lo_exclusive) + ", " + format(hi) + "]";
      fail(m);
      return std::nullopt;
    }
    return x;
  }

  std::optional<std::string> string(const std::string& key, bool nonempty = true) {
    const core::Json* v = find(key);
    if (!v) return std::nullopt;
    if (!v->is_string()) {
      wrong_type(key, *v, "a string");
      return std::nullopt;
    }
    auto s = v->get<std::string>();
    if (nonempty && s.empty()) {
      fail("'" + prefix_ + key + "' is empty");
      return std::nullopt;
    }
    return s;
  }

  std::optional<bool> boolean(const std::string& key) {
    const core::Json* v = find(key);
    if (!v) return std::nullopt;
    if (!v->is_boolean()) {
      wrong_type(key, *v, "true or false");
      return std::nullopt;
    }
    return v->get<bool>();
  }

  /// A nested object, or nullptr (reported).
  const core::Json* object(const std::string& key) {
    const core::Json* v = find(key);
    if (!v) return nullptr;
    if (!v->is_object()) {
      wrong_type(key, *v, "an object");
      return nullptr;
    }
    return v;
  }

  void fail(const std::string& what) { sink_.add(file_, what); }

 private:
  static std::string format(double x) {
    std::string s = core::Json(x).dump();
    return s;
  }
  std::nullopt_t wrong_type(const std::string& key, const core::Json& v, const char* expected) {
    std::string m = "'" + prefix_ + key + "' is ";
    m += v.dump();
    m += ", expected ";
    m += expected;
    fail(m);
    return std::nullopt;
  }
  std::nullopt_t out_of_range(const std::string& key, const core::Json& v, long long lo,
                              long long hi) {
    std::string m = "'" + prefix_ + key + "' is ";
    m += v.dump();
    m += ", out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    fail(m);
    return std::nullopt;
  }

  const core::Json& j_;
  const std::filesystem::path& file_;
  ProblemSink& sink_;
  std::string prefix_;
};

bool plain_file_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\\') == std::string::npos;
}

}  // namespace

std::optional<EpisodeInfo> parse_episode_info(const core::Json& j,
                                              const std::filesystem::path& file,
                                              ProblemSink& sink) {
  if (!j.is_object()) {
    sink.add(file, "expected a JSON object");
    return std::nullopt;
  }
  Fields f(j, file, sink);
  // Format and version first: fields of another format or a newer version mean nothing here.
  const auto format = f.string("format");
  if (!format) return std::nullopt;
  if (*format != kEpisodeFormat) {
    f.fail("format is '" + *format + "', expected '" + kEpisodeFormat + "'");
    return std::nullopt;
  }
  const auto version = f.integer("format_version", 1, 1000000);
  if (!version) return std::nullopt;
  if (*version > kEpisodeFormatVersion) {
    f.fail("format_version " + std::to_string(*version) +
           " is newer than this build of proprio supports (" +
           std::to_string(kEpisodeFormatVersion) + "); update proprio");
    return std::nullopt;
  }

  EpisodeInfo info;
  bool ok = true;
  info.format_version = static_cast<int>(*version);
  if (const core::Json* fc = f.find("frame_count"); fc && fc->is_number_integer() && *fc == 0) {
    f.fail("frame_count is 0: an empty episode (an episode has at least one frame)");
    ok = false;
  } else if (const auto n = f.integer("frame_count", 1, kMaxFrameCount)) {
    info.frame_count = static_cast<int>(*n);
  } else {
    ok = false;
  }
  if (const auto fps = f.number("fps", 0.0, kMaxFps))
    info.fps = *fps;
  else
    ok = false;

  if (const core::Json* image = f.object("image")) {
    Fields fi(*image, file, sink, "image.");
    const auto w = fi.integer("width", 1, kMaxImageSide);
    const auto h = fi.integer("height", 1, kMaxImageSide);
    if (w && h) {
      info.width = static_cast<int>(*w);
      info.height = static_cast<int>(*h);
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }

  if (const core::Json* arm = f.object("arm")) {
    Fields fa(*arm, file, sink, "arm.");
    const auto name = fa.string("name");
    const auto joints = fa.integer("joints", 0, kMaxJointCount);
    if (name && joints) {
      info.arm_name = *name;
      info.joint_count = static_cast<int>(*joints);
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }

  const auto masks = f.boolean("masks");
  const auto depth = f.boolean("depth");
  const auto stereo = f.boolean("stereo");
  if (masks && depth && stereo) {
    info.has_masks = *masks;
    info.has_depth = *depth;
    info.stereo = *stereo;
  } else {
    ok = false;
  }

  if (const core::Json* frames = f.object("frames")) {
    Fields ff(*frames, file, sink, "frames.");
    const auto storage = ff.string("storage");
    if (!storage) {
      ok = false;
    } else if (*storage == "png") {
      info.storage = FrameStorage::kPng;
    } else if (*storage == "video") {
      info.storage = FrameStorage::kVideo;
      const auto check_name = [&](const std::string& key, std::string& out) {
        const auto name = ff.string(key);
        if (!name) {
          ok = false;
        } else if (!plain_file_name(*name)) {
          ff.fail("'frames." + key + "' must be a file name in the episode directory, not '" +
                  *name + "'");
          ok = false;
        } else {
          out = *name;
        }
      };
      check_name("file", info.video_file);
      if (stereo && *stereo) check_name("file_right", info.video_file_right);
    } else {
      ff.fail("'frames.storage' is '" + *storage + "', expected 'png' or 'video'");
      ok = false;
    }
  } else {
    ok = false;
  }

  if (const core::Json* target = f.find("target")) {
    if (!target->is_null()) {
      if (const auto id = f.integer("target", 1, 65535)) {
        info.target = static_cast<int>(*id);
      } else {
        ok = false;
      }
    }
  } else {
    ok = false;
  }

  if (const core::Json* prov = f.object("provenance")) {
    try {
      info.provenance.run = core::provenance_from_json(*prov, file.string());
    } catch (const Error& e) {
      sink.add_error(file, e);
      ok = false;
    }
    Fields fp(*prov, file, sink, "provenance.");
    if (const auto source = fp.string("source")) {
      if (*source == "simulated") {
        info.provenance.source = Source::kSimulated;
        if (!info.provenance.run.seed) {
          fp.fail("a simulated episode needs its seed in 'provenance.seed'");
          ok = false;
        }
      } else if (*source == "real") {
        info.provenance.source = Source::kReal;
      } else {
        fp.fail("'provenance.source' is '" + *source + "', expected 'simulated' or 'real'");
        ok = false;
      }
    } else {
      ok = false;
    }
    if (const core::Json* scenario = fp.find("scenario")) {
      if (scenario->is_string()) {
        info.provenance.scenario = scenario->get<std::string>();
      } else if (!scenario->is_null()) {
        fp.fail("'provenance.scenario' is " + scenario->dump() + ", expected a string or null");
        ok = false;
      }
    } else {
      ok = false;
    }
    if (const core::Json* switches = fp.object("switches")) {
      info.provenance.switches = *switches;
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }
  if (!ok) return std::nullopt;
  return info;
}

}  // namespace detail
}  // namespace proprio::episode
