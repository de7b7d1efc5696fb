#include "proprio/core/csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {
namespace {

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

}  // namespace

std::string trim_csv_field(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

std::vector<std::string> split_csv_line(std::string_view line) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    out.push_back(trim_csv_field(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::string join_csv_line(const std::vector<std::string>& fields) {
  std::string s;
  for (const auto& x : fields) {
    if (!s.empty()) s += ',';
    s += x;
  }
  return s;
}

size_t CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw Error::in_file(source, "no column '" + name + "' in the header");
  return static_cast<size_t>(it - header.begin());
}

bool CsvTable::has_column(const std::string& name) const { return contains(header, name); }

double CsvTable::at(size_t row, size_t col) const {
  const auto& v = rows.at(row).at(col);
  if (!v) throw Error::at_line(source, lines.at(row), "column '" + header.at(col) + "' is empty");
  return *v;
}

CsvTable parse_csv(const std::string& text, const std::filesystem::path& source,
                   const CsvReadOptions& options) {
  CsvTable table;
  table.source = source;
  std::istringstream in(text);
  std::string line;
  long line_no = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim_csv_field(line);
    if (t.empty() || t[0] == '#') continue;
    auto fields = split_csv_line(t);
    if (!have_header) {
      for (const auto& f : fields) {
        if (f.empty()) throw Error::at_line(source, line_no, "empty column name in the header");
        if (std::count(fields.begin(), fields.end(), f) > 1) {
          throw Error::at_line(source, line_no, "column '" + f + "' appears twice in the header");
        }
      }
      if (!options.exact_columns.empty() && fields != options.exact_columns) {
        throw Error::at_line(source, line_no,
                             "header is '" + join_csv_line(fields) + "', expected '" +
                                 join_csv_line(options.exact_columns) + "'");
      }
      for (const auto& r : options.required_columns) {
        if (!contains(fields, r)) {
          throw Error::at_line(source, line_no, "header lacks column '" + r + "'");
        }
      }
      table.header = std::move(fields);
      have_header = true;
      continue;
    }
    if (fields.size() != table.header.size()) {
      throw Error::at_line(source, line_no,
                           "has " + std::to_string(fields.size()) + " columns, the header has " +
                               std::to_string(table.header.size()));
    }
    std::vector<std::optional<double>> row(fields.size());
    for (size_t c = 0; c < fields.size(); ++c) {
      const std::string& f = fields[c];
      if (f.empty()) {
        if (contains(options.optional_columns, table.header[c])) continue;
        throw Error::at_line(source, line_no, "column '" + table.header[c] + "' is empty");
      }
      double v = 0.0;
      const char* end = f.data() + f.size();
      const auto [ptr, ec] = std::from_chars(f.data(), end, v);
      if (ec != std::errc() || ptr != end) {
        throw Error::at_line(source, line_no,
                             "column '" + table.header[c] + "': '" + f + "' is not a number");
      }
      if (!std::isfinite(v)) {
        throw Error::at_line(source, line_no,
                             "column '" + table.header[c] + "': '" + f + "' is not finite");
      }
      row[c] = v;
    }
    table.rows.push_back(std::move(row));
    table.lines.push_back(line_no);
  }
  if (!have_header) throw Error::in_file(source, "empty file, expected a header line");
  if (table.rows.empty() && !options.allow_empty) throw Error::in_file(source, "no data rows");
  return table;
}

CsvTable read_csv(const std::filesystem::path& path, const CsvReadOptions& options) {
  return parse_csv(read_file(path), path, options);
}

std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::optional<double>>>& rows) {
  std::string out = join_csv_line(header) + "\n";
  char buf[64];
  for (const auto& row : rows) {
    for (size_t c = 0; c < row.size(); ++c) {
      if (c > 0) out += ',';
      if (row[c]) {
        // to_chars would write "nan" or "inf": a figure no reader of ours accepts. A bug upstream.
        if (!std::isfinite(*row[c])) {
          throw InternalError("refusing to write a non-finite number in CSV column '" +
                              (c < header.size() ? header[c] : std::to_string(c)) + "'");
        }
        const auto r = std::to_chars(buf, buf + sizeof buf, *row[c]);
        out.append(buf, r.ptr);
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace proprio::core
