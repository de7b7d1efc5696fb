#include "proprio/core/csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace {

std::string error_of(const std::string& text, const CsvReadOptions& o = {}) {
  try {
    parse_csv(text, "pts.csv", o);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Csv, ParsesHeaderAndRowsWithLineNumbers) {
  const auto t = parse_csv("# comment\nX, Y ,Z\n1,2,3\n\n-4.5,5e-3,6\n", "a.csv");
  ASSERT_EQ(t.header, (std::vector<std::string>{"X", "Y", "Z"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(t.at(1, 0), -4.5);
  EXPECT_DOUBLE_EQ(t.at(1, t.column("Y")), 5e-3);
  EXPECT_EQ(t.lines, (std::vector<long>{3, 5}));
}

TEST(Csv, RejectsWrongColumnCountNamingTheLine) {
  EXPECT_EQ(error_of("a,b\n1,2\n3\n"), "pts.csv:3: has 1 columns, the header has 2");
}

TEST(Csv, RejectsNanInfAndText) {
  EXPECT_EQ(error_of("a,b\n1,nan\n"), "pts.csv:2: column 'b': 'nan' is not finite");
  EXPECT_EQ(error_of("a,b\n1,inf\n"), "pts.csv:2: column 'b': 'inf' is not finite");
  EXPECT_EQ(error_of("a,b\n1,2x\n"), "pts.csv:2: column 'b': '2x' is not a number");
}

TEST(Csv, EmptyFieldsOnlyWhereOptional) {
  EXPECT_EQ(error_of("a,b\n1,\n"), "pts.csv:2: column 'b' is empty");
  CsvReadOptions o;
  o.optional_columns = {"b"};
  const auto t = parse_csv("a,b\n1,\n", "x", o);
  EXPECT_FALSE(t.rows[0][1].has_value());
  EXPECT_THROW((void)t.at(0, 1), Error);
}

TEST(Csv, HeaderChecks) {
  CsvReadOptions exact;
  exact.exact_columns = {"X", "Y", "Z", "u", "v"};
  EXPECT_EQ(error_of("X,Y,Z,u\n1,2,3,4\n", exact),
            "pts.csv:1: header is 'X,Y,Z,u', expected 'X,Y,Z,u,v'");
  CsvReadOptions req;
  req.required_columns = {"t"};
  EXPECT_EQ(error_of("a\n1\n", req), "pts.csv:1: header lacks column 't'");
  EXPECT_EQ(error_of("a,a\n1,1\n"), "pts.csv:1: column 'a' appears twice in the header");
  EXPECT_EQ(error_of(""), "pts.csv: empty file, expected a header line");
  EXPECT_EQ(error_of("a,b\n"), "pts.csv: no data rows");
}

TEST(Csv, FormatRoundTripsExactly) {
  const std::vector<std::vector<std::optional<double>>> rows = {
      {0.1, 1.0 / 3.0, std::nullopt}, {-1e-300, 123456789.123456789, 2.0}};
  const std::string text = format_csv({"a", "b", "c"}, rows);
  CsvReadOptions o;
  o.optional_columns = {"c"};
  const auto t = parse_csv(text, "x", o);
  ASSERT_EQ(t.rows.size(), 2u);
  for (size_t r = 0; r < rows.size(); ++r) {
    for (size_t c = 0; c < 3; ++c) EXPECT_EQ(t.rows[r][c], rows[r][c]);
  }
}

TEST(Csv, NonFiniteValuesAreRefusedNotWrittenAsNan) {
  EXPECT_THROW((void)format_csv({"a", "b"}, {{1.0, std::nan("")}}), InternalError);
  EXPECT_THROW((void)format_csv({"a"}, {{std::numeric_limits<double>::infinity()}}), InternalError);
  EXPECT_EQ(format_csv({"a"}, {{std::nullopt}}), "a\n\n");  // missing is empty, not nan
}

}  // namespace
}  // namespace proprio::core
