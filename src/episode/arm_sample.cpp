#include "proprio/episode/arm_sample.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "parse.hpp"
#include "proprio/core/csv.hpp"

namespace proprio::episode {

std::vector<std::string> arm_csv_header(int joint_count) {
  std::vector<std::string> h = {"frame", "t"};
  for (int k = 1; k <= joint_count; ++k) {
    std::string name = "q";  // built in steps: GCC 12's -Wrestrict misfires on "q" + string
    name += std::to_string(k);
    h.push_back(name);
  }
  for (const char* c : {"ee_x", "ee_y", "ee_z", "ee_u", "ee_v", "touching"}) h.emplace_back(c);
  return h;
}

namespace detail {
namespace {

using core::join_csv_line;
using core::split_csv_line;
using core::trim_csv_field;

/// Number of q columns in a header of the arm.csv form, or none when it is not of that form.
std::optional<int> joints_in_header(const std::vector<std::string>& h) {
  if (h.size() < 8) return std::nullopt;
  const int n = static_cast<int>(h.size()) - 8;
  if (h != arm_csv_header(n)) return std::nullopt;
  return n;
}

void append_number(std::string& out, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

/// "column 'COL': 'FIELD' WHAT", built by appending to one string.
std::string bad_field_message(const std::string& col, const std::string& field, const char* what) {
  std::string m = "column '";
  m += col;
  m += "': '";
  m += field;
  m += "' ";
  m += what;
  return m;
}

}  // namespace

std::optional<std::vector<ArmSample>> parse_arm_csv(const std::string& text,
                                                    const std::filesystem::path& file,
                                                    std::optional<int> joint_count,
                                                    ProblemSink& sink, int& rows) {
  std::istringstream in(text);
  std::string line;
  long line_no = 0;
  std::vector<std::string> header;
  std::vector<ArmSample> samples;
  bool ok = true;
  rows = 0;
  // The last valid row, for the sequence checks.
  std::optional<double> last_t;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim_csv_field(line);
    if (t.empty() || t[0] == '#') continue;
    auto fields = split_csv_line(t);
    if (header.empty()) {
      const auto found = joints_in_header(fields);
      const int n = joint_count.value_or(found.value_or(0));
      if (!found || (joint_count && *found != *joint_count)) {
        std::string m = "header is '" + join_csv_line(fields) + "', expected '" +
                        join_csv_line(arm_csv_header(n)) + "'";
        if (joint_count) m += " (episode.json says " + std::to_string(n) + " joints)";
        sink.add(file, m, line_no);
        return std::nullopt;
      }
      header = std::move(fields);
      continue;
    }
    const int frame_index = rows++;
    if (fields.size() != header.size()) {
      sink.add(file,
               "has " + std::to_string(fields.size()) + " columns, expected " +
                   std::to_string(header.size()) + " (" + join_csv_line(header) + ")",
               line_no);
      ok = false;
      continue;
    }
    std::vector<std::optional<double>> v(fields.size());
    bool row_ok = true;
    for (size_t c = 0; c < fields.size(); ++c) {
      const std::string& f = fields[c];
      const std::string& col = header[c];
      if (f.empty()) {
        if (col == "ee_u" || col == "ee_v") continue;
        sink.add(file, "column '" + col + "' is empty", line_no);
        row_ok = false;
        continue;
      }
      double x = 0.0;
      const char* end = f.data() + f.size();
      const auto [ptr, ec] = std::from_chars(f.data(), end, x);
      if (ec != std::errc() || ptr != end) {
        sink.add(file, bad_field_message(col, f, "is not a number"), line_no);
        row_ok = false;
      } else if (!std::isfinite(x)) {
        sink.add(file, bad_field_message(col, f, "is not finite"), line_no);
        row_ok = false;
      } else {
        v[c] = x;
      }
    }
    if (!row_ok) {
      ok = false;
      continue;
    }
    const size_t n = header.size();
    const int joints = static_cast<int>(n) - 8;
    // Columns: frame, t, q1..qN, ee_x, ee_y, ee_z, ee_u, ee_v, touching.
    const double frame = *v[0];
    if (frame != frame_index) {
      std::string m = "frame is ";
      append_number(m, frame);
      m += ", expected " + std::to_string(frame_index) + " (frames are numbered 0..N-1 in order)";
      sink.add(file, m, line_no);
      row_ok = false;
    }
    ArmSample s;
    s.t = *v[1];
    if (last_t && !(s.t > *last_t)) {
      std::string m = "t = ";
      append_number(m, s.t);
      m += " is not after the previous frame's t = ";
      append_number(m, *last_t);
      m += " (time must increase)";
      sink.add(file, m, line_no);
      row_ok = false;
    }
    last_t = s.t;
    s.q.resize(joints);
    for (int k = 0; k < joints; ++k) s.q[k] = *v[2 + k];
    s.ee = Eigen::Vector3d(*v[n - 6], *v[n - 5], *v[n - 4]);
    const auto& u = v[n - 3];
    const auto& vv = v[n - 2];
    if (u.has_value() != vv.has_value()) {
      sink.add(file, "ee_u and ee_v must both be given or both be empty", line_no);
      row_ok = false;
    } else if (u) {
      s.ee_image = Eigen::Vector2d(*u, *vv);
    }
    const double touching = *v[n - 1];
    if (touching != 0.0 && touching != 1.0) {
      std::string m = "touching is ";
      append_number(m, touching);
      m += ", expected 0 or 1";
      sink.add(file, m, line_no);
      row_ok = false;
    }
    s.touching = touching == 1.0;
    if (!row_ok) ok = false;
    samples.push_back(std::move(s));
  }
  if (header.empty()) {
    sink.add(file, "empty file, expected the header " +
                       join_csv_line(arm_csv_header(joint_count.value_or(0))));
    return std::nullopt;
  }
  if (rows == 0) {
    sink.add(file, "no data rows (an episode has at least one frame)");
    return std::nullopt;
  }
  if (!ok) return std::nullopt;
  return samples;
}

std::string format_arm_row(int frame, const ArmSample& s) {
  std::string out = std::to_string(frame);
  out += ',';
  append_number(out, s.t);
  for (Eigen::Index k = 0; k < s.q.size(); ++k) {
    out += ',';
    append_number(out, s.q[k]);
  }
  for (int k = 0; k < 3; ++k) {
    out += ',';
    append_number(out, s.ee[k]);
  }
  out += ',';
  if (s.ee_image) append_number(out, s.ee_image->x());
  out += ',';
  if (s.ee_image) append_number(out, s.ee_image->y());
  out += s.touching ? ",1\n" : ",0\n";
  return out;
}

}  // namespace detail
}  // namespace proprio::episode
