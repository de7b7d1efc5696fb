#pragma once
// Numeric CSV tables with a header line, as used by point files and arm logs. Every value is
// checked: a field that is not a finite number is an Error naming the file, line and column.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace proprio::core {

struct CsvReadOptions {
  /// Columns whose fields may be empty; an empty field is read as std::nullopt.
  std::vector<std::string> optional_columns;
  /// Columns that must be present (in any order; other columns are allowed).
  std::vector<std::string> required_columns;
  /// If not empty, the header must be exactly these columns in this order.
  std::vector<std::string> exact_columns;
  /// Refuse a file with no data rows.
  bool allow_empty = false;
};

/// A numeric table read from CSV.
struct CsvTable {
  std::filesystem::path source;
  std::vector<std::string> header;
  std::vector<std::vector<std::optional<double>>> rows;
  std::vector<long> lines;  ///< 1-based line number of each row in the source file

  /// Index of a column. Throws Error naming the file when it is absent.
  [[nodiscard]] size_t column(const std::string& name) const;
  [[nodiscard]] bool has_column(const std::string& name) const;
  /// The value at (row, column); throws Error naming the file and line when it is empty.
  [[nodiscard]] double at(size_t row, size_t col) const;
};

/// `s` without leading and trailing spaces, tabs and carriage returns.
std::string trim_csv_field(std::string_view s);
/// The trimmed comma-separated fields of one line ("a, b," gives "a", "b", "").
std::vector<std::string> split_csv_line(std::string_view line);
/// The fields joined by commas.
std::string join_csv_line(const std::vector<std::string>& fields);

/// Parses CSV text (`source` names it in messages). Separators: comma; surrounding spaces are
/// ignored; blank lines and lines starting with '#' are skipped.
CsvTable parse_csv(const std::string& text, const std::filesystem::path& source,
                   const CsvReadOptions& options = {});

/// Reads and parses a CSV file.
CsvTable read_csv(const std::filesystem::path& path, const CsvReadOptions& options = {});

/// Formats rows of numbers as CSV with a header line; values use the shortest representation
/// that reads back exactly, and std::nullopt becomes an empty field. Throws InternalError when a
/// value is NaN or Inf (a missing value is std::nullopt, never NaN).
std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::optional<double>>>& rows);

}  // namespace proprio::core
