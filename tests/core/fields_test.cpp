#include "proprio/core/fields.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace proprio::core {
namespace {

using ::testing::HasSubstr;

enum class Shape { kRound, kSquare };
constexpr ChoiceNames<Shape, 2> kShapeNames{{{"round", Shape::kRound}, {"square", Shape::kSquare}}};

struct Inner {
  float size = 16.0F;
};

struct Sample {
  int count = 3;
  double rate = 0.5;
  bool fast = false;
  std::uint64_t seed = 1;
  std::string label = "a";
  std::filesystem::path file = "x.txt";
  Shape shape = Shape::kRound;
  Inner inner;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.count, {"count", "How many", at_least(1), "n"});
    v(self.rate, {"rate", "A rate", positive_at_most(1.0)});
    v(self.fast, {"fast", "Go fast"});
    v(self.seed, {"seed", "Seed"});
    v(self.label, {"label", "A label"});
    v(self.file, {"file", "A file"});
    v.choice(self.shape, {"shape", "round or square"}, kShapeNames);
    v(self.inner.size, {"patch", "Patch side, px", positive()});
  }
};

TEST(Fields, ToJsonNamesEveryFieldWithItsValue) {
  Sample s;
  s.shape = Shape::kSquare;
  s.inner.size = 8.0F;
  const Json j = fields_to_json(s);
  EXPECT_EQ(j.size(), 8U);
  EXPECT_EQ(j.at("count"), 3);
  EXPECT_EQ(j.at("rate"), 0.5);
  EXPECT_EQ(j.at("fast"), false);
  EXPECT_EQ(j.at("label"), "a");
  EXPECT_EQ(j.at("file"), "x.txt");
  EXPECT_EQ(j.at("shape"), "square");
  EXPECT_EQ(j.at("patch"), 8.0);
}

TEST(Fields, JsonRoundTrip) {
  Sample s;
  s.count = 7;
  s.rate = 0.25;
  s.fast = true;
  s.seed = std::numeric_limits<std::uint64_t>::max();
  s.label = "b";
  s.file = "dir/y.bin";
  s.shape = Shape::kSquare;
  s.inner.size = 4.5F;
  Sample back;
  fields_from_json(fields_to_json(s), back, "t");
  EXPECT_EQ(fields_to_json(back), fields_to_json(s));
  EXPECT_EQ(back.seed, s.seed);
  EXPECT_EQ(back.shape, Shape::kSquare);
  EXPECT_EQ(back.file, s.file);
}

TEST(Fields, FromJsonKeepsWhatItDoesNotName) {
  Sample s;
  fields_from_json(Json{{"count", 9}}, s, "t");
  EXPECT_EQ(s.count, 9);
  EXPECT_EQ(s.rate, 0.5);
  EXPECT_EQ(s.label, "a");
}

std::string error_of(const Json& j) {
  Sample s;
  try {
    fields_from_json(j, s, "opts.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Fields, FromJsonRejectsWhatItCannotRead) {
  EXPECT_THAT(error_of(Json{{"colour", 1}}),
              HasSubstr("opts.json: unknown option 'colour' (known: count, rate"));
  EXPECT_EQ(error_of(Json{{"count", 1.5}}), "opts.json: count must be an integer");
  EXPECT_EQ(error_of(Json{{"count", "3"}}), "opts.json: count must be an integer");
  EXPECT_EQ(error_of(Json{{"count", 1LL << 40}}), "opts.json: count is out of range");
  EXPECT_EQ(error_of(Json{{"seed", -1}}), "opts.json: seed must be >= 0");
  EXPECT_EQ(error_of(Json{{"fast", 1}}), "opts.json: fast must be true or false");
  EXPECT_EQ(error_of(Json{{"rate", "x"}}), "opts.json: rate must be a number");
  EXPECT_EQ(error_of(Json{{"shape", "oval"}}),
            "opts.json: shape must be round or square (it is 'oval')");
  EXPECT_EQ(error_of(Json::array()), "opts.json: must be a JSON object");
}

TEST(Fields, BoundsCheckNamesTheFirstFieldOutside) {
  Sample s;
  EXPECT_NO_THROW(check_field_bounds(s, "sample"));
  s.count = 0;
  try {
    check_field_bounds(s, "sample");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "sample: count must be >= 1 (it is 0)");
  }
  s.count = 1;
  s.rate = 0.0;  // the lower bound is open
  EXPECT_THROW(check_field_bounds(s, "sample"), Error);
  s.rate = 1.0;  // the upper bound is closed
  EXPECT_NO_THROW(check_field_bounds(s, "sample"));
  s.rate = std::nan("");
  try {
    check_field_bounds(s, "sample");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "sample: rate must be in (0, 1] (it is NaN)");
  }
  s.rate = 1.0;
  s.inner.size = -std::numeric_limits<float>::infinity();
  EXPECT_THROW(check_field_bounds(s, "sample"), Error);
}

TEST(Fields, BoundsDescribeThemselves) {
  EXPECT_EQ(at_least(0).describe(), ">= 0");
  EXPECT_EQ(positive().describe(), "> 0");
  EXPECT_EQ(between(1, 10).describe(), "in [1, 10]");
  EXPECT_EQ(positive_at_most(0.5).describe(), "in (0, 0.5]");
  EXPECT_EQ(Bounds{}.describe(), "");
  EXPECT_EQ(finite_at_least(0).describe(), "finite, >= 0");
  EXPECT_TRUE(finite_at_least(0).contains(1e300));
  EXPECT_FALSE(finite_at_least(0).contains(std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(Bounds{}.bounded());
  EXPECT_TRUE(at_least(0).bounded());
  EXPECT_FALSE(Bounds{}.contains(std::nan("")));
}

TEST(Fields, ChoiceNames) {
  EXPECT_EQ(choice_name(Shape::kSquare, kShapeNames), "square");
  EXPECT_EQ(choice_list(kShapeNames), "round or square");
  constexpr ChoiceNames<int, 3> three{{{"a", 1}, {"b", 2}, {"c", 3}}};
  EXPECT_EQ(choice_list(three), "a, b or c");
  EXPECT_THROW((void)choice_name(4, three), InternalError);
}

// A Result-style description: a nested described struct, vectors, an optional and a derived value.
struct Point {
  int step = 0;
  double value = 0.0;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.step, {"step", "The step"});
    v(self.value, {"value", "The value"});
  }
};

struct Record {
  std::string name = "run";
  std::vector<Point> trace;
  std::vector<int> counts;
  std::optional<double> final_value;
  Point best;
  Json extra = Json::object();
  [[nodiscard]] double twice() const { return 2.0 * best.value; }

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.name, {"name", "A name"});
    v(self.trace, {"trace", "Points"});
    v(self.counts, {"counts", "Counts"});
    v(self.final_value, {"final", "The last value, when there is one"});
    v(self.best, {"best", "The best point"});
    v(self.extra, {"extra", "Free-form JSON"});
    v(self.twice(), {"twice", "Twice the best value (derived)"});
  }
};

TEST(Fields, ResultJsonNestsObjectsArraysAndOptionals) {
  Record r;
  r.trace = {{1, 0.5}, {2, 0.25}};
  r.best = {2, 0.25};
  Json doc = Json::object();
  doc["format"] = "x";
  fields_into_json(r, doc);
  EXPECT_EQ(doc.dump(),
            R"({"best":{"step":2,"value":0.25},"counts":[],"extra":{},"format":"x","name":"run",)"
            R"("trace":[{"step":1,"value":0.5},{"step":2,"value":0.25}],"twice":0.5})");
  r.final_value = 0.125;
  r.counts = {3, 4};
  const Json full = fields_to_json(r);
  EXPECT_EQ(full["final"], 0.125);
  EXPECT_EQ(full["counts"], Json::array({3, 4}));
  EXPECT_EQ(field_names<Record>().size(), 7U);
}

// Maps are objects keyed by the map's keys; or_null keeps an empty optional's key (as null);
// matrix_rows and vector_values turn anything with rows()/cols() or data()/size() into arrays.
struct Table {
  std::map<std::string, Point> by_name;
  std::optional<int> maybe;
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.by_name, {"by_name", "Points by name"});
    v(or_null(self.maybe), {"maybe", "An optional always listed"});
    v(self.maybe, {"maybe_left_out", "An optional left out when empty"});
  }
};

struct TwoByTwo {
  [[nodiscard]] int rows() const { return 2; }
  [[nodiscard]] int cols() const { return 2; }
  double operator()(int r, int c) const { return 10.0 * r + c; }
};

TEST(Fields, MapsOptionalsAsNullAndMatrices) {
  Table t;
  t.by_name["b"] = {2, 0.5};
  t.by_name["a"] = {1, 0.25};
  EXPECT_EQ(fields_to_json(t).dump(),
            R"({"by_name":{"a":{"step":1,"value":0.25},"b":{"step":2,"value":0.5}},"maybe":null})");
  t.maybe = 3;
  EXPECT_EQ(fields_to_json(t)["maybe"], 3);
  EXPECT_EQ(fields_to_json(t)["maybe_left_out"], 3);
  EXPECT_EQ(Json(matrix_rows(TwoByTwo{})).dump(), "[[0.0,1.0],[10.0,11.0]]");
  const std::vector<float> v{1.5F, 2.5F};
  EXPECT_EQ(vector_values(v), (std::vector<double>{1.5, 2.5}));
}

}  // namespace
}  // namespace proprio::core
