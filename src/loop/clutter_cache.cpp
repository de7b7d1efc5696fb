#include "proprio/loop/clutter_cache.hpp"

#include <algorithm>
#include <cstring>
#include <system_error>
#include <type_traits>
#include <utility>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::loop {

namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kDescriptorColumns = 128;

void put_u32(std::string& out, std::size_t v) {
  const auto x = static_cast<std::uint32_t>(v);
  char b[sizeof x];
  std::memcpy(b, &x, sizeof x);
  out.append(b, sizeof x);
}

// Reads the bytes in order; every read is checked against the bytes left.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  [[nodiscard]] std::size_t left() const { return bytes_.size() - at_; }
  bool u32(std::uint32_t& v) {
    if (left() < sizeof v) return false;
    std::memcpy(&v, bytes_.data() + at_, sizeof v);
    at_ += sizeof v;
    return true;
  }
  bool take(std::size_t n, std::string_view& out) {
    if (left() < n) return false;
    out = bytes_.substr(at_, n);
    at_ += n;
    return true;
  }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

// A manifest member as an integer in [lo, hi]: a JSON integer, not a float rounded.
int manifest_int(const core::Json& p, const char* key, int fallback, int lo, int hi,
                 const fs::path& file, std::size_t push) {
  const auto it = p.find(key);
  if (it == p.end()) {
    if (fallback < lo) {
      throw Error::in_file(file, "push " + std::to_string(push) + ": missing '" + key + "'");
    }
    return fallback;
  }
  if (!it->is_number_integer()) {
    throw Error::in_file(file,
                         "push " + std::to_string(push) + ": '" + key + "' must be an integer");
  }
  const auto v = it->get<std::int64_t>();
  if (v < lo || v > hi) {
    throw Error::in_file(file, "push " + std::to_string(push) + ": '" + key + "' must be in [" +
                                   std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return static_cast<int>(v);
}

template <typename T>
T manifest_get(const core::Json& p, const char* key, const fs::path& file, std::size_t push) {
  const auto it = p.find(key);
  const bool ok = it != p.end() && (std::is_same_v<T, bool> ? it->is_boolean() : it->is_string());
  if (!ok) {
    throw Error::in_file(file, "push " + std::to_string(push) + ": '" + key +
                                   "' missing or not a " +
                                   (std::is_same_v<T, bool> ? "boolean" : "string"));
  }
  return it->template get<T>();
}

}  // namespace

std::string clutter_views_bytes(std::string_view key, const ClutterViews& views) {
  std::string out(kClutterViewsMagic, 4);
  put_u32(out, kClutterViewsVersion);
  put_u32(out, key.size());
  out.append(key);
  put_u32(out, views.size());
  for (const auto& f : views) {
    put_u32(out, f.size());
    for (const auto& d : f) {
      const cv::Mat c = d.isContinuous() ? d : d.clone();
      put_u32(out, static_cast<std::size_t>(c.rows));
      put_u32(out, static_cast<std::size_t>(c.cols));
      out.append(reinterpret_cast<const char*>(c.data), c.total() * 4);
    }
  }
  return out;
}

std::optional<ClutterViews> parse_clutter_views(std::string_view bytes, std::string_view key,
                                                std::size_t fractions) {
  ByteReader in(bytes);
  std::string_view magic;
  std::uint32_t version = 0;
  if (!in.take(4, magic) || magic != std::string_view(kClutterViewsMagic, 4) || !in.u32(version) ||
      version != kClutterViewsVersion) {
    return std::nullopt;
  }
  std::uint32_t key_size = 0;
  std::string_view k;
  std::uint32_t n_fractions = 0;
  if (!in.u32(key_size) || key_size != key.size() || !in.take(key_size, k) || k != key ||
      !in.u32(n_fractions) || n_fractions != fractions) {
    return std::nullopt;
  }
  // Each fraction takes at least its count (4 bytes): a count the bytes cannot hold is refused
  // before the fractions are allocated.
  if (in.left() / 4 < fractions) return std::nullopt;
  ClutterViews out(fractions);
  for (auto& views : out) {
    std::uint32_t n = 0;
    // Each view takes at least its rows and cols (8 bytes).
    if (!in.u32(n) || n > kClutterViewsMaxViews || in.left() / 8 < n) return std::nullopt;
    views.reserve(n);
    for (std::uint32_t v = 0; v < n; ++v) {
      std::uint32_t rows = 0;
      std::uint32_t cols = 0;
      if (!in.u32(rows) || !in.u32(cols) || rows > kClutterViewsMaxRows ||
          cols != kDescriptorColumns) {
        return std::nullopt;
      }
      const std::size_t size = std::size_t{rows} * cols * sizeof(float);
      std::string_view data;
      if (!in.take(size, data)) return std::nullopt;  // before the matrix is allocated
      cv::Mat d(static_cast<int>(rows), static_cast<int>(cols), CV_32F);
      if (size > 0) std::memcpy(d.data, data.data(), size);
      views.push_back(d);
    }
  }
  if (in.left() != 0) return std::nullopt;  // more than the header says
  return out;
}

std::optional<ClutterViews> read_clutter_views(const fs::path& file, std::string_view key,
                                               std::size_t fractions) {
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  return parse_clutter_views(core::read_file(file), key, fractions);
}

void write_clutter_views(const fs::path& file, std::string_view key, const ClutterViews& views) {
  core::write_file_atomic(file, clutter_views_bytes(key, views));
}

ClutterManifestMatch match_clutter_manifest(const core::Json& manifest,
                                            const core::Json& recording) {
  if (!manifest.is_object()) return ClutterManifestMatch::kOtherFormat;
  const auto format = manifest.find("format");
  const auto version = manifest.find("format_version");
  if (format == manifest.end() || version == manifest.end() || *format != kClutterCacheFormat ||
      !version->is_number_integer() || *version != kClutterCacheVersion) {
    return ClutterManifestMatch::kOtherFormat;
  }
  const auto r = manifest.find("recording");
  if (r == manifest.end() || *r != recording) return ClutterManifestMatch::kOtherOptions;
  return ClutterManifestMatch::kYes;
}

std::vector<ClutterPush> clutter_manifest_pushes(const core::Json& manifest, const fs::path& file,
                                                 std::uint64_t seed, const std::string& object,
                                                 int trial, const fs::path& trial_dir) {
  if (!manifest.is_object()) throw Error::in_file(file, "expected a JSON object");
  const auto list = manifest.find("pushes");
  if (list == manifest.end() || !list->is_array()) {
    throw Error::in_file(file, "'pushes' missing or not an array");
  }
  if (list->size() > kClutterManifestMaxPushes) {
    throw Error::in_file(file,
                         "more than " + std::to_string(kClutterManifestMaxPushes) + " pushes");
  }
  std::vector<ClutterPush> out;
  out.reserve(list->size());
  for (std::size_t i = 0; i < list->size(); ++i) {
    const core::Json& p = (*list)[i];
    if (!p.is_object()) {
      throw Error::in_file(file, "push " + std::to_string(i) + ": expected a JSON object");
    }
    const auto ep = manifest_get<std::string>(p, "episode", file, i);
    const fs::path rel(ep);
    const bool inside =
        !rel.has_root_path() &&
        std::none_of(rel.begin(), rel.end(), [](const fs::path& part) { return part == ".."; });
    if (!inside) {
      throw Error::in_file(file, "push " + std::to_string(i) + ": episode '" + ep +
                                     "' is not inside the trial's directory");
    }
    ClutterPush c;
    c.seed = seed;
    c.object = object;
    c.trial = trial;
    c.index = manifest_int(p, "index", -1, 0, static_cast<int>(kClutterManifestMaxPushes), file, i);
    c.outcome = manifest_get<std::string>(p, "outcome", file, i);
    c.moved_intended = manifest_get<bool>(p, "moved_intended", file, i);
    c.only_intended = manifest_get<bool>(p, "only_intended", file, i);
    c.replaced = manifest_int(p, "replaced", 0, 0, 1000, file, i);
    c.attempts = manifest_int(p, "attempts", 1, 1, 1000, file, i);
    if (const auto f = p.find("failed"); f != p.end()) {
      const bool strings =
          f->is_array() && f->size() <= 1000 &&
          std::all_of(f->begin(), f->end(), [](const core::Json& s) { return s.is_string(); });
      if (!strings) {
        throw Error::in_file(file, "push " + std::to_string(i) +
                                       ": 'failed' must be an array of at most 1000 strings");
      }
      c.failed = f->get<std::vector<std::string>>();
    }
    if (!ep.empty()) c.episode = (trial_dir / rel).lexically_normal().generic_string();
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace proprio::loop
