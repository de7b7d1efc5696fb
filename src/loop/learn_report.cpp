#include "proprio/loop/learn_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/text.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/geometry/image_file.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/mot_model_io.hpp"
#include "report_html.hpp"

namespace proprio::loop {

namespace fs = std::filesystem;
using core::Json;
using report::escape;
using report::fixed;
using report::percent;

void LearnReportOptions::validate() const {
  core::check_field_bounds(*this, "report");
  require(!dir.empty(), "report: the run directory is required");
}

std::string LearnReportResult::brief() const {
  const LearnReportSummary& s = summary;
  std::string b = core::cat({"wrote ", s.page.string(), " (", std::to_string(s.pushes_drawn),
                             " of ", std::to_string(s.pushes), " pushes drawn, ",
                             std::to_string(s.image_files), " images in ", s.images.string()});
  if (s.headline_accuracy >= 0) {
    b += core::cat({"; held-out accuracy (headline) ", percent(s.headline_accuracy)});
  }
  if (s.mot_accuracy >= 0) b += core::cat({"; held-out MoT accuracy ", percent(s.mot_accuracy)});
  if (s.argmax_accuracy >= 0) b += core::cat({", argmax ", percent(s.argmax_accuracy)});
  if (!s.complete) b += "; the run is INCOMPLETE";
  return b + ")";
}

namespace {

constexpr const char* kLearnFormat = "proprio.learn";
constexpr int kLearnFormatVersion = 1;
constexpr const char* kNotRecorded = "<p class=\"missing\">Not recorded.</p>";
// Words shown in the vocabulary's per-class histograms at most (beyond, the chart is omitted).
constexpr int kMaxHistogramWords = 4096;
// Rows of the table of pushes at most (a hostile learn.json may list millions).
constexpr std::size_t kMaxPushRows = 5000;
// Per-class word images (DIR/words/) shown at most.
constexpr int kMaxWordImages = 64;

// ---- reading learn.json -------------------------------------------------------------------------

// Typed access to learn.json: every problem is an Error naming the file and the member.
class Reader {
 public:
  explicit Reader(fs::path file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw Error::in_file(file_, core::cat({"\"", where, "\" ", problem}));
  }
  const Json& required(const Json& obj, const std::string& key, const std::string& where) const {
    const Json* m = optional(obj, key);
    if (m == nullptr) fail(where == key ? key : core::cat({where, "/", key}), "is missing");
    return *m;
  }
  static const Json* optional(const Json& obj, const std::string& key) {
    if (!obj.is_object()) return nullptr;
    const auto it = obj.find(key);
    if (it == obj.end() || it->is_null()) return nullptr;
    return &*it;
  }
  std::string string(const Json& v, const std::string& where) const {
    if (!v.is_string()) fail(where, "must be a string");
    return v.get<std::string>();
  }
  double number(const Json& v, const std::string& where) const {
    if (!v.is_number()) fail(where, "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(where, "must be finite");
    return x;
  }
  long long integer(const Json& v, const std::string& where) const {
    if (!v.is_number_integer()) fail(where, "must be an integer");
    return v.get<long long>();
  }
  int count(const Json& v, const std::string& where) const {
    const long long n = integer(v, where);
    if (n < 0 || n > 1'000'000'000) fail(where, "must be a count (0 to 10^9)");
    return static_cast<int>(n);
  }
  bool boolean(const Json& v, const std::string& where) const {
    if (!v.is_boolean()) fail(where, "must be true or false");
    return v.get<bool>();
  }
  const Json& array(const Json& v, const std::string& where) const {
    if (!v.is_array()) fail(where, "must be an array");
    return v;
  }
  const Json& object(const Json& v, const std::string& where) const {
    if (!v.is_object()) fail(where, "must be an object");
    return v;
  }
  // A path inside the run directory: relative, without "..".
  fs::path inside(const Json& v, const std::string& where) const {
    const std::string s = string(v, where);
    fs::path p(s);
    if (s.empty() || p.is_absolute()) fail(where, "must be a relative path inside the run");
    for (const auto& part : p) {
      if (part == "..") fail(where, "must not leave the run directory (\"..\")");
    }
    return p;
  }
  [[nodiscard]] const fs::path& file() const { return file_; }

 private:
  fs::path file_;
};

std::string at(const std::string& where, std::size_t i) {
  return core::cat({where, "/", std::to_string(i)});
}

struct Confusion {
  bool present = false;
  double accuracy = -1;
  std::vector<std::string> rows;
  std::vector<std::string> columns;
  std::vector<std::vector<long long>> counts;
  std::vector<long long> unclassified;  ///< per row; empty: not recorded
};

struct Plan {
  bool present = false;
  cv::Point2d start_px;
  cv::Point2d end_px;
  std::optional<cv::Point2d> start;
  std::optional<cv::Point2d> end;
  std::optional<double> cost;
};

/// A push's recorded durations are at most this long (robot_seconds, perception_cpu_seconds), s.
constexpr double kMaxSeconds = 1e6;

struct Push {
  int index = 0;
  std::string cls;
  fs::path dir;
  bool executed = false;
  Plan plan;
  int frames = -1;
  int views = -1;
  std::optional<bool> moved_intended;
  std::string outcome;
  double robot_seconds = -1;   ///< the push's duration on the robot's clock; -1 not recorded
  double perception_cpu = -1;  ///< its perception's processor seconds; -1 not recorded
};

struct ObjectRow {
  std::string cls;
  std::string truth;
  int pushes = -1;
  int views = -1;
  double purity = -1;
};

struct Stage {
  std::string name;
  double seconds = 0;
};

// learn.json's "headline" (LearnHeadlineFigure; absent before session 32).
struct Headline {
  bool present = false;
  std::string classifier;
  std::string what;
  double accuracy = -1;
  std::vector<std::string> names;
  std::vector<int> held_out;
  std::vector<double> per_object;
};

struct Run {
  bool complete = false;
  Headline headline;
  Json options;
  std::vector<ObjectRow> objects;
  std::vector<Push> pushes;
  bool held_out = false;
  int views_per_object = -1;
  Confusion mot;
  Confusion argmax;
  bool timing = false;
  std::vector<Stage> stages;
  std::string clock;
  int vocabulary_words = -1;
  fs::path vocabulary_file = "vocabulary.vocab";
  int topics_count = -1;
  fs::path topics_file = "lda.model";
  fs::path model_file = "model.mot";
};

cv::Point2d point(const Reader& r, const Json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 2) r.fail(where, "must be an array of 2 numbers");
  return {r.number(v[0], at(where, 0)), r.number(v[1], at(where, 1))};
}

Confusion read_confusion(const Reader& r, const Json& v, const std::string& where) {
  r.object(v, where);
  Confusion c;
  c.present = true;
  if (const Json* a = Reader::optional(v, "accuracy")) {
    c.accuracy = r.number(*a, where + "/accuracy");
    if (c.accuracy < 0 || c.accuracy > 1) r.fail(where + "/accuracy", "must be in [0, 1]");
  }
  const Json& rows = r.array(r.required(v, "rows", where), where + "/rows");
  const Json& cols = r.array(r.required(v, "columns", where), where + "/columns");
  const Json& counts = r.array(r.required(v, "counts", where), where + "/counts");
  for (std::size_t i = 0; i < rows.size(); ++i)
    c.rows.push_back(r.string(rows[i], at(where + "/rows", i)));
  for (std::size_t i = 0; i < cols.size(); ++i)
    c.columns.push_back(r.string(cols[i], at(where + "/columns", i)));
  if (counts.size() != rows.size())
    r.fail(where + "/counts", "must have one row per \"rows\" entry");
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const std::string w = at(where + "/counts", i);
    const Json& row = r.array(counts[i], w);
    if (row.size() != cols.size()) r.fail(w, "must have one count per \"columns\" entry");
    std::vector<long long> out;
    for (std::size_t j = 0; j < row.size(); ++j) out.push_back(r.count(row[j], at(w, j)));
    c.counts.push_back(std::move(out));
  }
  if (const Json* u = Reader::optional(v, "unclassified")) {
    r.array(*u, where + "/unclassified");
    if (u->size() != rows.size())
      r.fail(where + "/unclassified", "must have one count per \"rows\" entry");
    for (std::size_t i = 0; i < u->size(); ++i)
      c.unclassified.push_back(r.count((*u)[i], at(where + "/unclassified", i)));
  }
  return c;
}

Run read_learn_json(const fs::path& file) {
  const Reader r(file);
  const Json doc = core::parse_json(core::read_file(file, kMaxLearnJsonBytes), file);
  if (!doc.is_object()) throw Error::in_file(file, "must hold a JSON object");
  const std::string format = r.string(r.required(doc, "format", "format"), "format");
  if (format != kLearnFormat) {
    r.fail("format", core::cat({"is \"", format, "\", not \"", kLearnFormat, "\""}));
  }
  const long long version =
      r.integer(r.required(doc, "format_version", "format_version"), "format_version");
  if (version != kLearnFormatVersion) {
    r.fail("format_version", core::cat({"is ", std::to_string(version), "; this build reads ",
                                        std::to_string(kLearnFormatVersion)}));
  }
  Run run;
  run.complete = r.boolean(r.required(doc, "complete", "complete"), "complete");
  if (const Json* o = Reader::optional(doc, "options")) run.options = r.object(*o, "options");

  const Json& objects = r.array(r.required(doc, "objects", "objects"), "objects");
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string w = at("objects", i);
    const Json& o = r.object(objects[i], w);
    ObjectRow row;
    row.cls = r.string(r.required(o, "class", w), w + "/class");
    if (const Json* v = Reader::optional(o, "truth")) row.truth = r.string(*v, w + "/truth");
    if (const Json* v = Reader::optional(o, "pushes")) row.pushes = r.count(*v, w + "/pushes");
    if (const Json* v = Reader::optional(o, "views")) row.views = r.count(*v, w + "/views");
    if (const Json* v = Reader::optional(o, "purity")) {
      row.purity = r.number(*v, w + "/purity");
      if (row.purity < 0 || row.purity > 1) r.fail(w + "/purity", "must be in [0, 1]");
    }
    run.objects.push_back(std::move(row));
  }

  const Json& pushes = r.array(r.required(doc, "pushes", "pushes"), "pushes");
  for (std::size_t i = 0; i < pushes.size(); ++i) {
    const std::string w = at("pushes", i);
    const Json& o = r.object(pushes[i], w);
    Push p;
    p.index = r.count(r.required(o, "index", w), w + "/index");
    p.executed = r.boolean(r.required(o, "executed", w), w + "/executed");
    if (const Json* v = Reader::optional(o, "class")) p.cls = r.string(*v, w + "/class");
    if (const Json* v = Reader::optional(o, "dir")) {
      p.dir = r.inside(*v, w + "/dir");
    } else {
      p.dir = fs::path("pushes") / core::printf_string("push_%03d", p.index);
    }
    if (const Json* v = Reader::optional(o, "plan")) {
      const std::string pw = w + "/plan";
      r.object(*v, pw);
      p.plan.present = true;
      p.plan.start_px = point(r, r.required(*v, "start_px", pw), pw + "/start_px");
      p.plan.end_px = point(r, r.required(*v, "end_px", pw), pw + "/end_px");
      if (const Json* s = Reader::optional(*v, "start")) p.plan.start = point(r, *s, pw + "/start");
      if (const Json* s = Reader::optional(*v, "end")) p.plan.end = point(r, *s, pw + "/end");
      if (const Json* s = Reader::optional(*v, "cost")) p.plan.cost = r.number(*s, pw + "/cost");
    }
    if (const Json* v = Reader::optional(o, "frames")) p.frames = r.count(*v, w + "/frames");
    if (const Json* v = Reader::optional(o, "views")) p.views = r.count(*v, w + "/views");
    if (const Json* v = Reader::optional(o, "moved_intended")) {
      p.moved_intended = r.boolean(*v, w + "/moved_intended");
    }
    if (const Json* v = Reader::optional(o, "outcome")) p.outcome = r.string(*v, w + "/outcome");
    const auto seconds = [&](const char* key, double& into) {
      if (const Json* v = Reader::optional(o, key)) {
        into = r.number(*v, core::cat({w, "/", key}));
        if (into < 0 || into > kMaxSeconds) {
          r.fail(core::cat({w, "/", key}), "must be 0 to 10^6 seconds");
        }
      }
    };
    seconds("robot_seconds", p.robot_seconds);
    seconds("perception_cpu_seconds", p.perception_cpu);
    run.pushes.push_back(std::move(p));
  }

  // A complete run has its held-out scores and timing; an interrupted one may lack them.
  const Json* held =
      run.complete ? &r.required(doc, "held_out", "held_out") : Reader::optional(doc, "held_out");
  if (held != nullptr) {
    r.object(*held, "held_out");
    run.held_out = true;
    if (const Json* v = Reader::optional(*held, "views_per_object")) {
      run.views_per_object = r.count(*v, "held_out/views_per_object");
    }
    if (const Json* v = Reader::optional(*held, "mot"))
      run.mot = read_confusion(r, *v, "held_out/mot");
    if (const Json* v = Reader::optional(*held, "argmax")) {
      run.argmax = read_confusion(r, *v, "held_out/argmax");
    }
  }
  if (const Json* h = Reader::optional(doc, "headline")) {
    r.object(*h, "headline");
    Headline& hl = run.headline;
    hl.present = true;
    hl.classifier = r.string(r.required(*h, "classifier", "headline"), "headline/classifier");
    hl.what = r.string(r.required(*h, "what", "headline"), "headline/what");
    hl.accuracy = r.number(r.required(*h, "accuracy", "headline"), "headline/accuracy");
    if (hl.accuracy < 0 || hl.accuracy > 1) r.fail("headline/accuracy", "must be in [0, 1]");
    const Json& names = r.array(r.required(*h, "objects", "headline"), "headline/objects");
    const Json& held_out = r.array(r.required(*h, "held_out", "headline"), "headline/held_out");
    const Json& per = r.array(r.required(*h, "per_object", "headline"), "headline/per_object");
    if (held_out.size() != names.size() || per.size() != names.size()) {
      r.fail("headline", "must have as many held_out and per_object entries as objects");
    }
    for (std::size_t i = 0; i < names.size(); ++i) {
      hl.names.push_back(r.string(names[i], at("headline/objects", i)));
      hl.held_out.push_back(r.count(held_out[i], at("headline/held_out", i)));
      const double a = r.number(per[i], at("headline/per_object", i));
      if (a < 0 || a > 1) r.fail(at("headline/per_object", i), "must be in [0, 1]");
      hl.per_object.push_back(a);
    }
  }
  const Json* timing =
      run.complete ? &r.required(doc, "timing", "timing") : Reader::optional(doc, "timing");
  if (timing != nullptr) {
    run.timing = true;
    const Json* stages = timing;
    if (timing->is_object()) {  // also accepted: {"clock": ..., "stages": [...]}
      if (const Json* c = Reader::optional(*timing, "clock"))
        run.clock = r.string(*c, "timing/clock");
      stages = &r.required(*timing, "stages", "timing");
    }
    r.array(*stages, "timing");
    for (std::size_t i = 0; i < stages->size(); ++i) {
      const std::string w = at("timing", i);
      const Json& o = r.object((*stages)[i], w);
      Stage s;
      s.name = r.string(r.required(o, "stage", w), w + "/stage");
      s.seconds = r.number(r.required(o, "seconds", w), w + "/seconds");
      if (s.seconds < 0) r.fail(w + "/seconds", "must not be negative");
      if (const Json* c = Reader::optional(o, "clock"); c != nullptr && run.clock.empty()) {
        run.clock = r.string(*c, w + "/clock");
      }
      run.stages.push_back(std::move(s));
    }
  }
  if (const Json* c = Reader::optional(doc, "clock"); c != nullptr && run.clock.empty()) {
    run.clock = r.string(*c, "clock");
  }
  if (const Json* v = Reader::optional(doc, "vocabulary")) {
    r.object(*v, "vocabulary");
    if (const Json* n = Reader::optional(*v, "words"))
      run.vocabulary_words = r.count(*n, "vocabulary/words");
    if (const Json* f = Reader::optional(*v, "file"))
      run.vocabulary_file = r.inside(*f, "vocabulary/file");
  }
  if (const Json* v = Reader::optional(doc, "topics")) {
    r.object(*v, "topics");
    if (const Json* n = Reader::optional(*v, "count"))
      run.topics_count = r.count(*n, "topics/count");
    if (const Json* f = Reader::optional(*v, "file")) run.topics_file = r.inside(*f, "topics/file");
  }
  if (const Json* v = Reader::optional(doc, "model")) run.model_file = r.inside(*v, "model");
  return run;
}

// ---- decisions.jsonl ----------------------------------------------------------------------------

struct Decisions {
  int lines = 0;
  int skipped_long = 0;
  bool truncated = false;
  std::uintmax_t bytes = 0;
  std::vector<std::pair<std::string, int>> events;  // by count, most first
  std::vector<std::string> shown;                   // the first lines, as read
};

Decisions read_decisions(const fs::path& file, int max_shown) {
  Decisions d;
  d.bytes = core::regular_file_size(file);
  std::string text = core::read_file_head(file, kMaxDecisionBytes);
  if (d.bytes > text.size()) {
    d.truncated = true;
    const auto last = text.rfind('\n');
    text.resize(last == std::string::npos ? 0 : last + 1);
  }
  std::map<std::string, int> events;
  std::size_t pos = 0;
  long line_no = 0;
  while (pos < text.size()) {
    const auto nl = text.find('\n', pos);
    const std::size_t end = nl == std::string::npos ? text.size() : nl;
    const std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (line.size() > kMaxDecisionLineBytes) {
      ++d.skipped_long;
      continue;
    }
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    Json j;
    try {
      j = core::parse_json(line, file);
    } catch (const Error&) {
      throw Error::at_line(file, line_no, "not a JSON object (one decision a line)");
    }
    if (!j.is_object()) throw Error::at_line(file, line_no, "not a JSON object");
    ++d.lines;
    const auto it = j.find("event");
    const std::string event =
        it != j.end() && it->is_string() ? it->get<std::string>() : "(no event)";
    if (events.size() < 64 || events.count(event) > 0) {
      ++events[event];
    } else {
      ++events["(other events)"];
    }
    if (static_cast<int>(d.shown.size()) < max_shown) d.shown.emplace_back(line);
  }
  d.events.assign(events.begin(), events.end());
  std::stable_sort(d.events.begin(), d.events.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return d;
}

// ---- images -------------------------------------------------------------------------------------

// The letters of a file name that are safe in an href unescaped; others are %-encoded.
std::string url_part(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) != 0 || c == '-' || c == '_' || c == '.') {
      out += c;
    } else {
      out += core::printf_string("%%%02X", static_cast<unsigned>(u));
    }
  }
  return out;
}

// Writes the images drawn for the page into the staging directory; hrefs are relative to the page.
class ImageSink {
 public:
  ImageSink(fs::path dir, std::string href_prefix)
      : dir_(std::move(dir)), href_prefix_(std::move(href_prefix)) {}

  // Writes `image` as `name` (.jpg: JPEG quality 90; else PNG); returns its href.
  std::string write(const std::string& name, const cv::Mat& image) {
    std::vector<uchar> bytes;
    const bool jpeg = name.ends_with(".jpg");
    const std::vector<int> params =
        jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, 90} : std::vector<int>{};
    ensure(cv::imencode(jpeg ? ".jpg" : ".png", image, bytes, params),
           "report: cannot encode an image");
    core::write_file_atomic(
        dir_ / name, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
    ++count_;
    return href_prefix_ + url_part(name);
  }
  [[nodiscard]] int count() const { return count_; }

 private:
  fs::path dir_;
  std::string href_prefix_;
  int count_ = 0;
};

std::string img(const std::string& href, const std::string& alt, int width = 0, int height = 0) {
  std::string s = core::cat({"<img src=\"", escape(href), "\" alt=\"", escape(alt), "\""});
  if (width > 0 && height > 0) {
    s += core::printf_string(" width=\"%d\" height=\"%d\"", width, height);
  }
  return s + ">";
}

int clamp_px(double v, int size) {
  const double lim = 4.0 * std::max(size, 1);
  return static_cast<int>(std::lround(std::clamp(v, -lim, lim)));
}

// The planned path on the before image: a dark-outlined yellow arrow from start to end, a ring
// at the start.
cv::Mat draw_plan(const cv::Mat& before, const Plan& plan) {
  cv::Mat out = before.clone();
  if (!plan.present) return out;
  const int t = std::max(2, out.cols / 160);
  const cv::Point a(clamp_px(plan.start_px.x, out.cols), clamp_px(plan.start_px.y, out.rows));
  const cv::Point b(clamp_px(plan.end_px.x, out.cols), clamp_px(plan.end_px.y, out.rows));
  const double len = std::max(1.0, std::hypot(b.x - a.x, b.y - a.y));
  const double tip = std::min(0.4, 14.0 * t / len);
  cv::arrowedLine(out, a, b, cv::Scalar(0, 0, 0), t + 3, cv::LINE_AA, 0, tip);
  cv::arrowedLine(out, a, b, cv::Scalar(0, 230, 255), t, cv::LINE_AA, 0, tip);
  cv::circle(out, a, 3 * t, cv::Scalar(0, 0, 0), t + 2, cv::LINE_AA);
  cv::circle(out, a, 3 * t, cv::Scalar(0, 230, 255), t, cv::LINE_AA);
  return out;
}

// The mask over the frame: pixels of the mask tinted green, its outline yellow.
cv::Mat draw_overlay(const cv::Mat& frame, cv::Mat mask) {
  if (mask.size() != frame.size()) cv::resize(mask, mask, frame.size(), 0, 0, cv::INTER_NEAREST);
  cv::Mat binary = mask > 127;
  cv::Mat tint(frame.size(), frame.type(), cv::Scalar(60, 200, 60));
  cv::Mat blended;
  cv::addWeighted(frame, 0.5, tint, 0.5, 0, blended);
  cv::Mat out = frame.clone();
  blended.copyTo(out, binary);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(binary, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  cv::drawContours(out, contours, -1, cv::Scalar(0, 230, 255), std::max(1, frame.cols / 320),
                   cv::LINE_AA);
  return out;
}

constexpr int kColourMap = cv::COLORMAP_VIRIDIS;

cv::Mat draw_map(const cv::Mat& map) {
  cv::Mat out;
  cv::applyColorMap(map, out, kColourMap);
  return out;
}

// The colour map's colours at `n` evenly spaced levels, "#rrggbb".
std::vector<std::string> colour_stops(int n) {
  cv::Mat ramp(1, n, CV_8U);
  for (int i = 0; i < n; ++i) ramp.at<uchar>(0, i) = static_cast<uchar>(255 * i / (n - 1));
  cv::Mat c;
  cv::applyColorMap(ramp, c, kColourMap);
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) {
    const auto p = c.at<cv::Vec3b>(0, i);
    out.push_back(core::printf_string("#%02x%02x%02x", p[2], p[1], p[0]));
  }
  return out;
}

// ---- the page -----------------------------------------------------------------------------------

constexpr const char* kStyle = R"(
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;margin:0;color:#1d2430;background:#f6f7f9}
header{background:#1d2430;color:#fff;padding:14px 24px}header h1{margin:0;font-size:22px}
nav{position:sticky;top:0;background:#e9edf2;padding:6px 24px;border-bottom:1px solid #cfd6df;z-index:1}
nav a{margin-right:14px;color:#1d4f86;text-decoration:none}
main{padding:8px 24px 40px;max-width:1400px}
section{background:#fff;border:1px solid #dde2e8;border-radius:6px;padding:8px 18px 14px;margin:16px 0}
h2{font-size:18px;margin:8px 0}h3{font-size:15px;margin:10px 0 4px}
.missing{color:#8a5a00;font-style:italic}.banner{background:#fff3cd;border:1px solid #e0b000;padding:8px 12px;border-radius:4px}
.ok{color:#1b7a32}.bad{color:#b3261e}
table{border-collapse:collapse;margin:6px 0}td,th{border:1px solid #dde2e8;padding:3px 8px;text-align:left;vertical-align:top}
th{background:#f0f3f6}td.num{text-align:right;font-variant-numeric:tabular-nums}
.grid{display:flex;flex-wrap:wrap;gap:14px}.card{border:1px solid #e3e7ec;border-radius:6px;padding:6px 10px;background:#fbfcfd}
figure{margin:0}figure img{max-width:420px;width:100%;height:auto;display:block;border:1px solid #ccd}
figcaption{font-size:12px;color:#555}.pair{display:flex;gap:10px;flex-wrap:wrap}
.headline{font-size:16px}.headline b{font-size:20px}
pre{background:#f3f5f7;padding:8px;overflow:auto;max-height:420px;font-size:12px}
img.broken{outline:3px solid #b3261e}
)";

// Waits for every image and records what loaded (the headless-browser test reads it; a reader
// sees a warning when an image is missing).
constexpr const char* kScript = R"(<script>
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0;
  for (var i = 0; i < imgs.length; i++) {
    if (imgs[i].complete && imgs[i].naturalWidth > 0) ok++; else imgs[i].classList.add('broken');
  }
  var c = document.getElementById('image-check');
  c.setAttribute('data-loaded', String(ok));
  c.setAttribute('data-total', String(imgs.length));
  c.setAttribute('data-state', ok === imgs.length ? 'ok' : 'failed');
  c.textContent = ok === imgs.length ? 'All ' + ok + ' images loaded.'
                                     : (imgs.length - ok) + ' of ' + imgs.length + ' images did not load.';
  c.className = ok === imgs.length ? 'ok' : 'bad';
});
</script>)";

std::string section_start(std::string_view id, std::string_view title, std::string_view intro) {
  return core::cat({"<section id=\"", id, "\"><h2>", escape(title), "</h2>",
                    intro.empty() ? "" : "<p>", escape(intro), intro.empty() ? "" : "</p>"});
}

std::string count_or_dash(long long n) { return n >= 0 ? std::to_string(n) : "\xE2\x80\x93"; }

// The JSON value as short text for a table cell (strings without quotes).
std::string json_text(const Json& v) {
  std::string s =
      v.is_string() ? v.get<std::string>() : v.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (s.size() > 200) s = s.substr(0, 200) + "\xE2\x80\xA6";
  return s;
}

struct Context {
  const LearnReportOptions& options;
  const fs::path& dir;
  const Run& run;
  ImageSink& sink;
  std::map<std::string, std::string> truth_of;  // class -> truth name
};

std::string class_label(const Context& c, const std::string& cls) {
  const auto it = c.truth_of.find(cls);
  if (it == c.truth_of.end() || it->second.empty()) return cls;
  return core::cat({cls, " (", it->second, ")"});
}

// The object a confusion column stands for: its class's truth (learn.json "objects"), or, for a
// column named "object_1 (book)" (as the held-out scoring names them), the name in brackets.
std::string column_truth(const Context& c, const std::string& col) {
  if (const auto it = c.truth_of.find(col); it != c.truth_of.end()) return it->second;
  const auto open = col.rfind(" (");
  if (open != std::string::npos && col.size() > open + 3 && col.back() == ')') {
    const std::string cls = col.substr(0, open);
    if (const auto it = c.truth_of.find(cls); it != c.truth_of.end()) return it->second;
    return col.substr(open + 2, col.size() - open - 3);
  }
  return {};
}

// Held-out views of row r classified right: a column is right for the object its class was
// learned from (the rule of `proprio learn`'s printout and LearnSummary); every view of the row
// counts, unclassified ones too. `mapped`: some column stands for the row's object.
struct RowScore {
  long long total = 0;
  long long correct = 0;
  bool mapped = false;
};

RowScore row_score(const Context& c, const Confusion& conf, std::size_t r) {
  RowScore s;
  for (std::size_t j = 0; j < conf.columns.size(); ++j) {
    s.total += conf.counts[r][j];
    if (conf.columns[j] == conf.rows[r] || column_truth(c, conf.columns[j]) == conf.rows[r]) {
      s.mapped = true;
      s.correct += conf.counts[r][j];
    }
  }
  if (r < conf.unclassified.size()) s.total += conf.unclassified[r];
  return s;
}

// The held-out accuracy of a confusion, computed from its counts by row_score (never from the
// diagonal: the columns are the robot's classes, in no row's order); its "accuracy" member only
// when it has no counts. -1: none.
double held_out_accuracy(const Context& c, const Confusion& conf) {
  if (!conf.present) return -1;
  long long total = 0;
  long long correct = 0;
  for (std::size_t r = 0; r < conf.rows.size(); ++r) {
    const RowScore rs = row_score(c, conf, r);
    total += rs.total;
    correct += rs.correct;
  }
  if (total > 0) return static_cast<double>(correct) / static_cast<double>(total);
  return conf.accuracy;
}

std::string summary_section(const Context& c, const Decisions& dec, bool complete) {
  const Run& run = c.run;
  std::string s = section_start("summary", "Summary", "");
  if (!complete) {
    s += "<p class=\"banner\">This run is <b>incomplete</b> (interrupted or still running): what "
         "it recorded so far is shown.</p>";
  }
  int executed = 0;
  for (const Push& p : run.pushes) executed += p.executed ? 1 : 0;
  double total = 0;
  for (const Stage& st : run.stages) total += st.seconds;
  s += "<p class=\"headline\">";
  // A class counts as learned when it has views (a run may stop before it reaches every class;
  // an old learn.json without view counts: every class listed).
  long learned = 0;
  for (const ObjectRow& o : run.objects) learned += o.views != 0 ? 1 : 0;
  s += core::cat({"<b>", std::to_string(learned), "</b> of ", std::to_string(run.objects.size()),
                  " objects learned from <b>", std::to_string(executed), "</b> executed pushes (",
                  std::to_string(run.pushes.size()), " planned)"});
  if (run.headline.present) {
    s += core::cat({"; held-out accuracy (headline, ", escape(run.headline.what), ") <b>",
                    percent(run.headline.accuracy), "</b>"});
  }
  if (const double mot = held_out_accuracy(c, run.mot); mot >= 0) {
    s += core::cat({"; held-out accuracy: Mixture of Topics <b>", percent(mot), "</b>"});
    if (const double am = held_out_accuracy(c, run.argmax); am >= 0) {
      s += core::cat({", argmax of topics <b>", percent(am), "</b>"});
    }
  }
  if (run.timing) s += core::cat({"; ", fixed(total, 1), " s in all"});
  s += core::cat({"; ", std::to_string(dec.lines), " decisions logged.</p>"});
  s += "<p id=\"image-check\" data-state=\"pending\">Images: checking (needs JavaScript).</p>";
  s += "<h3>Options of the run</h3>";
  if (run.options.is_object() && !run.options.empty()) {
    s += "<table><tr><th>option</th><th>value</th></tr>";
    for (const auto& [k, v] : run.options.items()) {
      s += core::cat({"<tr><td>", escape(k), "</td><td>", escape(json_text(v)), "</td></tr>"});
    }
    s += "</table>";
  } else {
    s += kNotRecorded;
  }
  return s + "</section>";
}

std::string table_section(const Context& c) {
  std::string s = section_start("table", "The table as the robot saw it",
                                "The robot's first look at the table, before any push.");
  const fs::path table = c.dir / "table.png";
  if (fs::exists(table)) {
    const cv::Mat image = geometry::read_image(table, cv::IMREAD_COLOR);
    const std::string href = c.sink.write("table.jpg", image);
    s += core::cat({"<figure>", img(href, "the table", image.cols, image.rows),
                    "<figcaption>table.png</figcaption></figure>"});
  } else {
    s += kNotRecorded;
  }
  return s + "</section>";
}

struct PushImages {
  std::string plan, after, overlay, map;
  cv::Size size;
  cv::Size map_size;
};

std::string push_title(const Context& c, const Push& p) {
  std::string t = core::cat({"Push ", std::to_string(p.index)});
  if (!p.cls.empty()) t += core::cat({" \xC2\xB7 ", class_label(c, p.cls)});
  if (!p.outcome.empty()) t += core::cat({" \xC2\xB7 ", p.outcome});
  return t;
}

std::string pushes_table(const Context& c) {
  // A long list is folded so that the pictures stay near the top.
  std::string s = core::cat({"<details", c.run.pushes.size() <= 20 ? " open" : "", "><summary>All ",
                             std::to_string(c.run.pushes.size()), " pushes</summary>"});
  s += "<table><tr><th>push</th><th>class</th><th>executed</th><th>moved the intended "
       "object</th><th>frames</th><th>views</th><th>plan (world, "
       "m)</th><th>cost</th><th>outcome</th></tr>";
  for (std::size_t i = 0; i < c.run.pushes.size() && i < kMaxPushRows; ++i) {
    const Push& p = c.run.pushes[i];
    std::string plan = "\xE2\x80\x93";
    if (p.plan.start && p.plan.end) {
      plan = core::cat({"(", fixed(p.plan.start->x, 3), ", ", fixed(p.plan.start->y, 3),
                        ") \xE2\x86\x92 (", fixed(p.plan.end->x, 3), ", ", fixed(p.plan.end->y, 3),
                        ")"});
    }
    const std::string moved =
        p.moved_intended ? (*p.moved_intended ? "yes" : "no") : "\xE2\x80\x93";
    s += core::cat({"<tr><td class=\"num\"><a href=\"#push-",
                    std::to_string(p.index),
                    "\">",
                    std::to_string(p.index),
                    "</a></td><td>",
                    escape(class_label(c, p.cls)),
                    "</td><td>",
                    p.executed ? "yes" : "no",
                    "</td><td>",
                    moved,
                    "</td><td class=\"num\">",
                    count_or_dash(p.frames),
                    "</td><td class=\"num\">",
                    count_or_dash(p.views),
                    "</td><td>",
                    plan,
                    "</td><td class=\"num\">",
                    p.plan.cost ? fixed(*p.plan.cost, 3) : "\xE2\x80\x93",
                    "</td><td>",
                    escape(p.outcome),
                    "</td></tr>"});
  }
  s += "</table>";
  if (c.run.pushes.size() > kMaxPushRows) {
    s += core::cat({"<p class=\"missing\">", std::to_string(c.run.pushes.size() - kMaxPushRows),
                    " more pushes not listed.</p>"});
  }
  return s + "</details>";
}

std::string pushes_and_segmentation(const Context& c, int& drawn) {
  std::string pushes = section_start(
      "pushes", "Pushes",
      "Each push as planned and executed: the planned path of the pusher drawn on the look before "
      "the push (ring: start, arrow: end), and the look after it, the arm parked in both.");
  std::string seg = section_start(
      "segmentation", "Segmentation of the pushed objects",
      "The object the robot segmented from each push's motion: the mask used for its views over "
      "the frame (green, outlined), and the object probability map.");
  seg += report::colour_bar(colour_stops(9), "0", "1");
  pushes += pushes_table(c);
  if (c.run.pushes.empty()) {
    pushes += kNotRecorded;
    seg += kNotRecorded;
  }
  std::string push_cards = "<div class=\"grid\">";
  std::string seg_cards = "<div class=\"grid\">";
  int omitted = 0;
  for (const Push& p : c.run.pushes) {
    if (!p.executed) continue;
    if (drawn >= c.options.max_pushes) {
      ++omitted;
      continue;
    }
    const fs::path d = c.dir / p.dir;
    const std::string stem = core::printf_string("push_%03d_", p.index);
    const cv::Mat before = geometry::read_image(d / "before.png", cv::IMREAD_COLOR);
    const cv::Mat after = geometry::read_image(d / "after.png", cv::IMREAD_COLOR);
    const cv::Mat frame = geometry::read_image(d / "frame.png", cv::IMREAD_COLOR);
    const cv::Mat mask = geometry::read_image(d / "mask.png", cv::IMREAD_GRAYSCALE);
    const cv::Mat map = geometry::read_image(d / "map.png", cv::IMREAD_GRAYSCALE);
    double map_max = 0;
    cv::minMaxLoc(map, nullptr, &map_max);
    const std::string title = push_title(c, p);
    const std::string anchor = core::cat({"push-", std::to_string(p.index)});
    push_cards +=
        core::cat({"<div class=\"card\" id=\"", anchor, "\"><h3>", escape(title),
                   "</h3><div class=\"pair\"><figure>",
                   img(c.sink.write(stem + "plan.jpg", draw_plan(before, p.plan)),
                       "before, planned path", before.cols, before.rows),
                   "<figcaption>before", p.plan.present ? ", planned path" : " (no plan recorded)",
                   "</figcaption></figure><figure>",
                   img(c.sink.write(stem + "after.jpg", after), "after", after.cols, after.rows),
                   "<figcaption>after</figcaption></figure></div></div>"});
    seg_cards += core::cat(
        {"<div class=\"card\"><h3>", escape(title), "</h3><div class=\"pair\"><figure>",
         img(c.sink.write(stem + "overlay.jpg", draw_overlay(frame, mask)), "mask over frame",
             frame.cols, frame.rows),
         "<figcaption>mask over frame</figcaption></figure><figure>",
         img(c.sink.write(stem + "map.png", draw_map(map)), "probability map", map.cols, map.rows),
         "<figcaption>probability map (max ", fixed(map_max / 255.0, 2),
         ")</figcaption></figure></div></div>"});
    ++drawn;
  }
  push_cards += "</div>";
  seg_cards += "</div>";
  if (omitted > 0) {
    const std::string note = core::cat({"<p class=\"missing\">", std::to_string(omitted),
                                        " more executed pushes not drawn (--max-pushes ",
                                        std::to_string(c.options.max_pushes), ").</p>"});
    push_cards += note;
    seg_cards += note;
  }
  if (drawn == 0 && !c.run.pushes.empty()) seg += "<p class=\"missing\">No push was executed.</p>";
  return pushes + push_cards + "</section>" + seg + seg_cards + "</section>";
}

template <class F>
auto try_read(const fs::path& file, F&& read, std::string& problem)
    -> std::optional<decltype(read())> {
  if (!fs::exists(file)) return std::nullopt;
  try {
    return read();
  } catch (const Error& e) {
    problem = e.what();
    return std::nullopt;
  }
}

std::string problem_note(const std::string& problem) {
  return core::cat({"<p class=\"bad\">Could not be read: ", escape(problem), "</p>"});
}

struct Models {
  std::optional<features::Vocabulary> vocabulary;
  std::string vocabulary_problem;
  std::optional<topics::LdaModel> lda;
  std::string lda_problem;
  std::optional<topics::MotModelFile> mot;
  std::string mot_problem;
};

std::string words_section(const Context& c, const Models& m) {
  std::string s = section_start(
      "words", "Visual words",
      "The vocabulary the robot quantises its features with, and the words each learned object "
      "is expected to show (its Dirichlet mean over topics times the topics' word "
      "distributions).");
  if (m.vocabulary) {
    s += core::cat({"<p>", escape(c.run.vocabulary_file.string()), ": <b>",
                    std::to_string(m.vocabulary->size()), "</b> words of dimension ",
                    std::to_string(m.vocabulary->dimension()), ".</p>"});
  } else if (!m.vocabulary_problem.empty()) {
    s += problem_note(m.vocabulary_problem);
  } else if (c.run.vocabulary_words >= 0) {
    s += core::cat({"<p>", std::to_string(c.run.vocabulary_words),
                    " words (the vocabulary file is not in the run directory).</p>"});
  } else {
    s += kNotRecorded;
  }
  // Per-class word images written by the run.
  const fs::path words_dir = c.dir / "words";
  if (fs::is_directory(words_dir)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(words_dir)) {
      if (e.is_regular_file() && e.path().extension() == ".png") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    if (files.size() > static_cast<std::size_t>(kMaxWordImages)) files.resize(kMaxWordImages);
    s += "<h3>Word images</h3><div class=\"grid\">";
    for (std::size_t i = 0; i < files.size(); ++i) {
      const std::string name = files[i].stem().string();
      std::string problem;
      const auto image = try_read(
          files[i], [&] { return geometry::read_image(files[i], cv::IMREAD_COLOR); }, problem);
      s += "<figure class=\"card\">";
      if (image) {
        s += img(c.sink.write(core::printf_string("words_%03zu.png", i), *image), name, image->cols,
                 image->rows);
      } else {
        s += problem_note(problem);
      }
      s += core::cat({"<figcaption>", escape(class_label(c, name)), "</figcaption></figure>"});
    }
    s += "</div>";
  }
  if (m.lda && m.mot && m.lda->num_topics() == m.mot->model.num_topics()) {
    const int w = m.lda->num_words();
    if (w <= kMaxHistogramWords) {
      s += "<h3>Expected words per object</h3><div class=\"grid\">";
      const Eigen::MatrixXd beta = m.lda->topic_word();
      for (const auto& o : m.mot->model.objects) {
        const Eigen::VectorXd pw = beta.transpose() * o.dirichlet.mean();
        std::vector<report::Bar> bars;
        bars.reserve(static_cast<std::size_t>(w));
        for (int i = 0; i < w; ++i) {
          const auto word = static_cast<std::size_t>(i);
          bars.push_back({word < m.lda->vocabulary.size() ? m.lda->vocabulary[word]
                                                          : core::cat({"w", std::to_string(i)}),
                          pw(i), fixed(pw(i), 4)});
        }
        s += core::cat(
            {"<div class=\"card\"><h3>", escape(class_label(c, o.name)), "</h3>",
             report::vertical_bars(bars, 0, class_label(c, o.name), "word", "#3b75af", 420, 150),
             "</div>"});
      }
      s += "</div>";
    }
  } else if (m.lda && m.mot) {
    s += "<p class=\"bad\">The LDA model and the object model have different numbers of "
         "topics.</p>";
  }
  return s + "</section>";
}

std::string topics_section(const Context& c, const Models& m) {
  std::string s = section_start("topics", "Topics",
                                "The LDA topics the views are described by: each topic's most "
                                "probable visual words.");
  if (m.lda) {
    const topics::LdaModel& lda = *m.lda;
    s += core::cat({"<p>", escape(c.run.topics_file.string()), ": <b>",
                    std::to_string(lda.num_topics()), "</b> topics over ",
                    std::to_string(lda.num_words()), " words (alpha ", fixed(lda.alpha, 3),
                    ", eta ", fixed(lda.eta, 3), ").</p><div class=\"grid\">"});
    const Eigen::MatrixXd beta = lda.topic_word();
    const int n = std::min(c.options.top_words, lda.num_words());
    double top = 0;
    for (int k = 0; k < lda.num_topics(); ++k) top = std::max(top, beta.row(k).maxCoeff());
    for (int k = 0; k < lda.num_topics(); ++k) {
      std::vector<report::Bar> bars;
      for (const int wi : lda.top_words(k, n)) {
        const std::string word = static_cast<std::size_t>(wi) < lda.vocabulary.size()
                                     ? lda.vocabulary[static_cast<std::size_t>(wi)]
                                     : core::cat({"word ", std::to_string(wi)});
        bars.push_back({word, beta(k, wi), fixed(beta(k, wi), 4)});
      }
      const std::string name = core::cat({"z", std::to_string(k + 1)});
      s += core::cat({"<div class=\"card\"><h3>Topic ", name, "</h3>",
                      report::horizontal_bars(bars, top, core::cat({"top words of topic ", name}),
                                              "#5a9e6f", 330),
                      "</div>"});
    }
    s += "</div>";
  } else if (!m.lda_problem.empty()) {
    s += problem_note(m.lda_problem);
  } else if (c.run.topics_count >= 0) {
    s += core::cat({"<p>", std::to_string(c.run.topics_count),
                    " topics (the model file is not in the run directory).</p>"});
  } else {
    s += kNotRecorded;
  }
  return s + "</section>";
}

std::string models_section(const Context& c, const Models& m) {
  std::string s = section_start(
      "models", "Object models",
      "What the robot learned of each object: the pushes and views it learned it from, and its "
      "Dirichlet over topics (Mixture of Topics, eq 7.2): alpha per topic and the precision "
      "s = sum of alpha (how tightly the object's views gather at the mean). Truth and purity "
      "come from the simulator and only score the run.");
  if (c.run.objects.empty()) {
    s += kNotRecorded;
  } else {
    s += "<table><tr><th>class</th><th>truth</th><th>pushes</th><th>views</th><th>purity</th></tr>";
    for (const ObjectRow& o : c.run.objects) {
      s += core::cat({"<tr><td>", escape(o.cls), "</td><td>", escape(o.truth),
                      "</td><td class=\"num\">", count_or_dash(o.pushes), "</td><td class=\"num\">",
                      count_or_dash(o.views), "</td><td class=\"num\">",
                      o.purity >= 0 ? percent(o.purity) : "\xE2\x80\x93", "</td></tr>"});
    }
    s += "</table>";
  }
  if (m.mot) {
    const topics::MotModel& mot = m.mot->model;
    s += core::cat({"<p>", escape(c.run.model_file.string()), ": ",
                    std::to_string(mot.num_classes()), " objects over ",
                    std::to_string(mot.num_topics()), " topics.</p><div class=\"grid\">"});
    double top = 0;
    for (const auto& o : mot.objects) top = std::max(top, o.dirichlet.alpha().maxCoeff());
    for (const auto& o : mot.objects) {
      std::vector<report::Bar> bars;
      for (int k = 0; k < o.dirichlet.dim(); ++k) {
        const double a = o.dirichlet.alpha()(k);
        bars.push_back({core::cat({"z", std::to_string(k + 1)}), a, fixed(a, 3)});
      }
      s += core::cat(
          {"<div class=\"card\"><h3>", escape(class_label(c, o.name)), "</h3><p>precision s = ",
           fixed(o.dirichlet.precision(), 2), "; ", fixed(o.views, 0), " views</p>",
           report::vertical_bars(bars, top, core::cat({"alpha of ", class_label(c, o.name)}),
                                 "topic", "#b5651d", 360, 150),
           "</div>"});
    }
    s += "</div>";
  } else if (!m.mot_problem.empty()) {
    s += problem_note(m.mot_problem);
  } else {
    s += "<p class=\"missing\">The object model file is not recorded.</p>";
  }
  return s + "</section>";
}

std::string confusion_block(const Context& c, const Confusion& conf, const std::string& name,
                            double& accuracy_out) {
  std::string s = core::cat({"<h3>", escape(name), "</h3>"});
  if (!conf.present) return s + kNotRecorded;
  long long total = 0;
  std::vector<report::Bar> bars;
  std::string table = "<table><tr><th>truth \xE2\x86\x93 / class \xE2\x86\x92</th>";
  for (const std::string& col : conf.columns)
    table += core::cat({"<th>", escape(class_label(c, col)), "</th>"});
  table += "<th>accuracy</th></tr>";
  for (std::size_t r = 0; r < conf.rows.size(); ++r) {
    const RowScore rs = row_score(c, conf, r);
    const long long row_total = rs.total;
    const long long row_correct = rs.correct;
    const bool mapped = rs.mapped;
    total += row_total;
    table += core::cat({"<tr><th>", escape(conf.rows[r]), "</th>"});
    for (std::size_t j = 0; j < conf.columns.size(); ++j) {
      const double f = row_total > 0 ? static_cast<double>(conf.counts[r][j]) / row_total : 0;
      table += core::cat({"<td class=\"num\" style=\"background:", report::cell_shade(f), "\">",
                          std::to_string(conf.counts[r][j]), "</td>"});
    }
    const double acc = row_total > 0 && mapped ? static_cast<double>(row_correct) / row_total : -1;
    table +=
        core::cat({"<td class=\"num\">", acc >= 0 ? percent(acc) : "\xE2\x80\x93", "</td></tr>"});
    if (acc >= 0) {
      const auto ci =
          report::wilson_interval(static_cast<int>(row_correct), static_cast<int>(row_total));
      bars.push_back({conf.rows[r], acc,
                      core::cat({percent(acc), " [", percent(ci.low), ", ", percent(ci.high), "]"}),
                      ci.low, ci.high});
    } else {
      bars.push_back({conf.rows[r], 0, "no class learned for it"});
    }
  }
  table += "</table>";
  const double acc = held_out_accuracy(c, conf);
  accuracy_out = acc;
  s += core::cat({"<p class=\"headline\">accuracy <b>", acc >= 0 ? percent(acc) : "\xE2\x80\x93",
                  "</b> of ", std::to_string(total), " held-out views</p>", table,
                  "<p>Per object, with Wilson 95% intervals:</p>",
                  report::horizontal_bars(bars, 1.0, core::cat({name, ": accuracy per object"}),
                                          "#3b75af", 620)});
  return s;
}

std::string held_out_section(const Context& c, LearnReportSummary& summary) {
  std::string s = section_start(
      "held-out", "Held-out views: confusion and accuracy",
      "Ground-truth views of each object the robot never learned from, classified by the "
      "Mixture of Topics (eq 7.3) and by the argmax of their topics; rows are the true objects, "
      "columns the classes the robot made up; a class counts as right for the object it was "
      "learned from.");
  if (!c.run.held_out) return s + kNotRecorded + "</section>";
  if (c.run.views_per_object >= 0) {
    s += core::cat({"<p>", std::to_string(c.run.views_per_object), " views per object.</p>"});
  }
  if (const Headline& h = c.run.headline; h.present) {
    summary.headline_accuracy = h.accuracy;
    std::vector<report::Bar> bars;
    for (std::size_t i = 0; i < h.names.size(); ++i) {
      const int n = h.held_out[i];
      if (n <= 0) {
        bars.push_back({h.names[i], 0, "no held-out view with features"});
        continue;
      }
      const auto ci =
          report::wilson_interval(static_cast<int>(std::lround(h.per_object[i] * n)), n);
      bars.push_back({h.names[i], h.per_object[i],
                      core::cat({percent(h.per_object[i]), " [", percent(ci.low), ", ",
                                 percent(ci.high), "]"}),
                      ci.low, ci.high});
    }
    s +=
        core::cat({"<h3>Headline: ", escape(h.what), "</h3><p class=\"headline\">accuracy <b>",
                   percent(h.accuracy), "</b> (learn's headline figure, --headline ",
                   escape(h.classifier == "pooled_per_view" ? std::string("pooled") : h.classifier),
                   ")</p><p>Per object, with Wilson 95% intervals:</p>",
                   report::horizontal_bars(bars, 1.0, core::cat({h.what, ": accuracy per object"}),
                                           "#3b75af", 620)});
  }
  s += confusion_block(c, c.run.mot, "Mixture of Topics", summary.mot_accuracy);
  s += confusion_block(c, c.run.argmax, "Argmax of topics", summary.argmax_accuracy);
  return s + "</section>";
}

// The perception of each executed push (processor seconds) against how long the push lasted on
// the robot's clock (issue 21's speed goal); empty when the run did not record them.
std::string perception_line(const std::vector<Push>& pushes) {
  std::vector<double> ratio;
  double cpu = 0;
  double robot = 0;
  int faster = 0;
  for (const Push& p : pushes) {
    // A push shorter than a millisecond gives no ratio worth printing (nor an infinite one).
    if (!p.executed || p.robot_seconds < 1e-3 || p.perception_cpu < 0) continue;
    ratio.push_back(p.perception_cpu / p.robot_seconds);
    cpu += p.perception_cpu;
    robot += p.robot_seconds;
    faster += p.perception_cpu < p.robot_seconds ? 1 : 0;
  }
  if (ratio.empty()) return {};
  std::sort(ratio.begin(), ratio.end());
  const auto n = static_cast<double>(ratio.size());
  constexpr std::string_view kWhat =
      "<p>Perception of a push (its segmentation, word updates and the recognition after it; "
      "processor time, every thread) against the push's own duration on the robot's clock: ";
  return core::cat({kWhat, fixed(cpu / n, 2), " s against ", fixed(robot / n, 2),
                    " s a push on average; ", std::to_string(faster), " of ",
                    std::to_string(ratio.size()),
                    " pushes perceived in less time than they lasted (largest ratio ",
                    fixed(ratio.back(), 2), ").</p>"});
}

std::string timing_section(const Context& c) {
  std::string s = section_start("timing", "Where the time went", "");
  if (!c.run.timing || c.run.stages.empty()) return s + kNotRecorded + "</section>";
  double total = 0;
  for (const Stage& st : c.run.stages) total += st.seconds;
  std::vector<report::Bar> bars;
  for (const Stage& st : c.run.stages) {
    const double f = total > 0 ? st.seconds / total : 0;
    bars.push_back(
        {st.name, st.seconds, core::cat({fixed(st.seconds, 2), " s (", percent(f), ")"})});
  }
  s += core::cat({"<p>", fixed(total, 1), " s in all",
                  c.run.clock.empty() ? std::string(" (clock not recorded)")
                                      : core::cat({" (", escape(c.run.clock), " time)"}),
                  ".</p>", report::horizontal_bars(bars, 0, "seconds per stage", "#7a4fa3", 640)});
  return s + perception_line(c.run.pushes) + "</section>";
}

std::string decisions_section(const Decisions& d) {
  std::string s = section_start("decisions", "Decisions",
                                "Every decision the robot logged (decisions.jsonl), by kind.");
  if (d.lines == 0) {
    s += "<p class=\"missing\">No decisions logged.</p>";
  } else {
    std::vector<report::Bar> bars;
    for (const auto& [event, n] : d.events)
      bars.push_back({event, static_cast<double>(n), std::to_string(n)});
    s += report::horizontal_bars(bars, 0, "decisions by event", "#3b75af", 560);
  }
  if (d.truncated) {
    s += core::cat({"<p class=\"missing\">The log has ", std::to_string(d.bytes),
                    " bytes; only its first ", std::to_string(kMaxDecisionBytes),
                    " were read.</p>"});
  }
  if (d.skipped_long > 0) {
    s += core::cat({"<p class=\"missing\">", std::to_string(d.skipped_long), " lines longer than ",
                    std::to_string(kMaxDecisionLineBytes), " bytes were skipped.</p>"});
  }
  if (!d.shown.empty()) {
    s += core::cat({"<details><summary>The first ", std::to_string(d.shown.size()), " of ",
                    std::to_string(d.lines), " decisions</summary><pre>"});
    for (const std::string& line : d.shown) s += escape(line) + "\n";
    s += "</pre></details>";
  }
  return s + "</section>";
}

std::vector<fs::path> inputs_of(const fs::path& dir, const Run& run) {
  std::vector<fs::path> in{
      dir / "learn.json",        dir / "decisions.jsonl", dir / "table.png",    dir / "words",
      dir / run.vocabulary_file, dir / run.topics_file,   dir / run.model_file, dir / "pushes"};
  for (const Push& p : run.pushes) {
    for (const char* name : {"before.png", "after.png", "frame.png", "mask.png", "map.png"}) {
      in.push_back(dir / p.dir / name);
    }
  }
  return in;
}

}  // namespace

std::vector<fs::path> learn_report_inputs(const fs::path& dir) {
  return inputs_of(dir, read_learn_json(dir / "learn.json"));
}

int count_learn_decisions(const fs::path& file) { return read_decisions(file, 0).lines; }

fs::path learn_report_page(const LearnReportOptions& options) {
  return options.out.empty() ? options.dir / "report.html" : options.out;
}

fs::path learn_report_images(const LearnReportOptions& options) {
  const fs::path out = learn_report_page(options);
  return out.parent_path() / out.stem();
}

LearnReportResult write_learn_report(const LearnReportOptions& options,
                                     const core::Provenance& provenance) {
  options.validate();
  const fs::path& dir = options.dir;
  if (!fs::is_directory(dir)) throw Error::in_file(dir, "not a directory (the run directory)");
  const fs::path learn_json = dir / "learn.json";
  const fs::path decisions_file = dir / "decisions.jsonl";
  const fs::path out = learn_report_page(options);
  require(!out.filename().empty() && !out.stem().empty(),
          core::cat({"--out: ", out.string(), " is not a file name"}));
  const fs::path images = learn_report_images(options);
  if (fs::is_directory(out)) throw Error::in_file(out, "is a directory, not a page to write");
  if (fs::exists(out) && !options.overwrite) {
    throw Error::in_file(out, "exists (use --overwrite to replace it)");
  }

  const Run run = read_learn_json(learn_json);
  std::vector<fs::path> inputs = inputs_of(dir, run);
  core::require_output_not_input(out, inputs, "--out");
  inputs.push_back(dir);
  core::require_output_not_input(images, inputs, "--out (its image directory)");
  const Decisions decisions = read_decisions(decisions_file, options.max_decisions);

  Models models;
  const fs::path vfile = dir / run.vocabulary_file;
  models.vocabulary = try_read(
      vfile, [&] { return features::read_vocabulary(vfile); }, models.vocabulary_problem);
  const fs::path lfile = dir / run.topics_file;
  models.lda = try_read(
      lfile, [&] { return topics::load_lda_model(lfile); }, models.lda_problem);
  const fs::path mfile = dir / run.model_file;
  models.mot = try_read(
      mfile, [&] { return topics::load_mot_model(mfile); }, models.mot_problem);

  LearnReportResult result;
  LearnReportSummary& summary = result.summary;
  summary.page = out;
  summary.images = images;
  summary.complete = run.complete && !fs::exists(dir / "INCOMPLETE");
  summary.pushes = static_cast<int>(run.pushes.size());
  summary.classes = static_cast<int>(run.objects.size());
  summary.decisions = decisions.lines;

  core::StagedDirectory staged(images, options.overwrite);
  ImageSink sink(staged.staging_path(), url_part(images.filename().string()) + "/");
  Context c{options, dir, run, sink, {}};
  for (const ObjectRow& o : run.objects) c.truth_of[o.cls] = o.truth;

  std::string body = summary_section(c, decisions, summary.complete);
  body += table_section(c);
  body += pushes_and_segmentation(c, summary.pushes_drawn);
  body += words_section(c, models);
  body += topics_section(c, models);
  body += models_section(c, models);
  body += held_out_section(c, summary);
  body += timing_section(c);
  body += decisions_section(decisions);
  summary.image_files = sink.count();

  std::string page =
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" "
      "content=\"width=device-width,initial-scale=1\"><title>proprio learn: ";
  page += escape(dir.filename().empty() ? dir.parent_path().filename().string()
                                        : dir.filename().string());
  page += "</title><style>";
  page += kStyle;
  page += "</style></head><body><header><h1>What the robot learned</h1><div>";
  page += escape(fs::absolute(dir).lexically_normal().string());
  page += "</div></header><nav>";
  const char* const nav_titles[] = {"Summary", "Table",  "Pushes",   "Segmentation", "Words",
                                    "Topics",  "Models", "Held-out", "Time",         "Decisions"};
  for (std::size_t i = 0; i < kLearnReportSections.size(); ++i) {
    page += core::cat({"<a href=\"#", kLearnReportSections[i], "\">", nav_titles[i], "</a>"});
  }
  page += "</nav><main>";
  page += body;
  page += "</main>";
  page += kScript;
  page += "</body></html>\n";
  summary.page_bytes = page.size();

  result.document = core::result_document(kLearnReportFormat, 1, provenance);
  result.options = options;
  core::fields_into_json(result, result.document);
  // The images directory's marker (core::kResultMarkers): a later --overwrite may replace it.
  core::write_json_atomic(staged.staging_path() / "summary.json", result.document);
  staged.commit();
  core::write_file_atomic(out, page);
  result.message = core::first_line(result.brief());
  return result;
}

}  // namespace proprio::loop
