// `proprio calib ...` end to end: the built tool on files written here, good runs and bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "../geometry/synthetic.hpp"
#include "../support/schema_check.hpp"
#include "../support/temp_dir.hpp"
#include "cli_run.hpp"
#include "proprio/core/csv.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/geometry/camera.hpp"

namespace proprio {
namespace {
namespace fs = std::filesystem;
using test::line_count;
using test::run_cli;

// A temporary folder per test, removed at the end.
class CalibCli : public ::testing::Test {
 protected:
  test::TempDir temp_{"proprio_calib_cli_"};
  fs::path dir_ = temp_.path();
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    core::write_file_atomic(dir_ / name, text);
    return path(name);
  }
  // Expects exit 2 with one stderr line that contains every piece of `expect`.
  static void expect_error(const test::CliResult& r, std::initializer_list<std::string> expect) {
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    for (const auto& e : expect) EXPECT_NE(r.err.find(e), std::string::npos) << r.err;
  }
};

using test::expect_schema_valid;

std::string dlt_csv(double noise_px, int n = 100, std::uint64_t seed = 5) {
  const geometry::Camera cam = geometry::testing::robot_camera();
  core::Rng rng(seed);
  auto world = geometry::testing::workspace_points(rng);
  std::vector<std::vector<std::optional<double>>> rows;
  for (int i = 0; i < n; ++i) {
    const auto& X = world[static_cast<size_t>(i)];
    const Eigen::Vector2d x = cam.project(X);
    rows.push_back(
        {X.x(), X.y(), X.z(), x.x() + rng.normal(0, noise_px), x.y() + rng.normal(0, noise_px)});
  }
  return core::format_csv({"X", "Y", "Z", "u", "v"}, rows);
}

TEST_F(CalibCli, HelpForEveryVerb) {
  for (const char* verb : {"dlt", "triangulate", "backproject", "uncertainty", "stereo"}) {
    const auto r = run_cli(std::string("calib ") + verb + " --help");
    EXPECT_EQ(r.code, 0) << verb;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << verb;
  }
  EXPECT_NE(run_cli("calib dlt --help").out.find("X,Y,Z,u,v"), std::string::npos);
}

TEST_F(CalibCli, DltOnNoisySyntheticPoints) {
  const std::string pts = write("pts.csv", dlt_csv(0.5));
  const auto r = run_cli("calib dlt --points " + pts + " --out " + path("calib.yml") +
                         " --width 640 --height 480 --json " + path("dlt.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("DLT on 100 points"), std::string::npos) << r.out;
  const geometry::Camera truth = geometry::testing::robot_camera();
  const geometry::Camera cam = geometry::read_calib(path("calib.yml"));
  EXPECT_NEAR(cam.K(0, 0), truth.K(0, 0), 0.01 * truth.K(0, 0));
  EXPECT_LT((cam.center() - truth.center()).norm(), 0.01);
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
  const core::Json j = core::read_json(path("dlt.json"));
  EXPECT_EQ(j["format"], "proprio.calib.dlt");
  EXPECT_LT(j["rms_px"].get<double>(), 0.85);
  EXPECT_EQ(j["points"], 100);
  EXPECT_EQ(j["P"].size(), 3u);
  EXPECT_EQ(j["residuals_px"].size(), 100u);
  expect_schema_valid("calib_dlt.schema.json", path("dlt.json"));

  // Exact pixels: essentially zero error.
  const std::string exact = write("exact.csv", dlt_csv(0.0));
  const auto e = run_cli("calib dlt --points " + exact + " --out " + path("exact.yml") +
                         " --json " + path("exact.json"));
  ASSERT_EQ(e.code, 0) << e.err;
  EXPECT_LT(core::read_json(path("exact.json"))["rms_px"].get<double>(), 1e-6);
}

TEST_F(CalibCli, DltBadInput) {
  const std::string out = " --out " + path("calib.yml");
  expect_error(run_cli("calib dlt --points " + path("missing.csv") + out), {path("missing.csv")});

  const std::string cols = write("cols.csv", "X,Y,u,v\n1,2,3,4\n");
  expect_error(run_cli("calib dlt --points " + cols + out),
               {cols + ":1:", "header is 'X,Y,u,v', expected 'X,Y,Z,u,v'"});

  const std::string nan = write("nan.csv", "X,Y,Z,u,v\n0,0,0,1,1\n0.1,0.2,nan,100,200\n");
  expect_error(run_cli("calib dlt --points " + nan + out), {nan + ":3:", "not finite"});

  const std::string few = write("few.csv", dlt_csv(0.0, 5));
  expect_error(run_cli("calib dlt --points " + few + out),
               {few + ": DLT needs at least 6 point pairs, got 5"});

  std::string plane = "X,Y,Z,u,v\n";
  for (int i = 0; i < 12; ++i) {
    plane += std::to_string(0.05 * i) + "," + std::to_string(0.1 * (i % 3)) + ",0," +
             std::to_string(100 + 10 * i) + "," + std::to_string(200 + 7 * (i % 3)) + "\n";
  }
  const std::string coplanar = write("coplanar.csv", plane);
  expect_error(run_cli("calib dlt --points " + coplanar + out), {coplanar + ": ", "coplanar"});

  const std::string empty = write("empty.csv", "");
  expect_error(run_cli("calib dlt --points " + empty + out), {empty + ": empty file"});
  EXPECT_FALSE(fs::exists(path("calib.yml")));  // nothing written on failure
}

class CalibCliStereo : public CalibCli {
 protected:
  geometry::Camera c1_ = geometry::testing::robot_camera();
  geometry::Camera c2_ = geometry::testing::second_camera();
  void SetUp() override {
    CalibCli::SetUp();
    geometry::write_calib(dir_ / "c1.yml", c1_);
    geometry::write_calib(dir_ / "c2.yml", c2_);
  }
};

TEST_F(CalibCliStereo, TriangulateRoundTrip) {
  core::Rng rng(8);
  const auto world = geometry::testing::workspace_points(rng);
  std::vector<std::vector<std::optional<double>>> rows;
  for (const auto& X : world) {
    const Eigen::Vector2d a = c1_.project(X), b = c2_.project(X);
    rows.push_back({a.x(), a.y(), b.x(), b.y()});
  }
  const std::string pts = write("uv.csv", core::format_csv({"u1", "v1", "u2", "v2"}, rows));
  for (const char* refine : {"", " --refine"}) {
    const auto r = run_cli("calib triangulate --calib1 " + path("c1.yml") + " --calib2 " +
                           path("c2.yml") + " --points " + pts + " --out " + path("xyz.csv") +
                           refine + " --json " + path("tri.json"));
    ASSERT_EQ(r.code, 0) << r.err;
    core::CsvReadOptions o;
    o.exact_columns = {"X", "Y", "Z"};
    const core::CsvTable t = core::read_csv(path("xyz.csv"), o);
    ASSERT_EQ(t.rows.size(), world.size());
    for (size_t i = 0; i < world.size(); ++i) {
      EXPECT_LT((Eigen::Vector3d(t.at(i, 0), t.at(i, 1), t.at(i, 2)) - world[i]).norm(), 1e-9);
    }
    const core::Json j = core::read_json(path("tri.json"));
    EXPECT_EQ(j["points"], 100);
    EXPECT_EQ(j["refined"], std::string(refine).empty() ? false : true);
    EXPECT_LT(j["rms_px"].get<double>(), 1e-6);
    expect_schema_valid("calib_triangulate.schema.json", path("tri.json"));
  }

  // Bad input: wrong columns, a missing calibration, parallel rays on line 3.
  const std::string cols = write("cols.csv", "u1,v1,u2\n1,2,3\n");
  const std::string args = "calib triangulate --calib1 " + path("c1.yml") + " --calib2 " +
                           path("c2.yml") + " --out " + path("o.csv") + " --points ";
  expect_error(run_cli(args + cols), {cols + ":1:", "expected 'u1,v1,u2,v2'"});
  expect_error(run_cli("calib triangulate --calib1 " + path("nope.yml") + " --calib2 " +
                       path("c2.yml") + " --out " + path("o.csv") + " --points " + pts),
               {path("nope.yml")});
  // The same camera twice: a fault of the calibrations (no baseline), named as such, not of a line
  // of the point file.
  const Eigen::Vector2d a = c1_.project(world[0]);
  std::string same = "u1,v1,u2,v2\n# a comment\n";
  same += std::to_string(a.x()) + "," + std::to_string(a.y()) + "," + std::to_string(a.x()) + "," +
          std::to_string(a.y()) + "\n";
  const std::string degenerate = write("same.csv", same);
  expect_error(run_cli("calib triangulate --calib1 " + path("c1.yml") + " --calib2 " +
                       path("c1.yml") + " --out " + path("o.csv") + " --points " + degenerate),
               {path("c1.yml") + ": triangulation: the two cameras have the same centre",
                "(calib1: " + path("c1.yml") + ")"});
}

TEST_F(CalibCliStereo, BackprojectRoundTrip) {
  std::vector<Eigen::Vector3d> world;
  std::vector<std::vector<std::optional<double>>> rows;
  for (int i = 0; i < 20; ++i) {
    world.emplace_back(-0.3 + 0.03 * i, 0.1 + 0.02 * i, 0.0);
    const Eigen::Vector2d x = c1_.project(world.back());
    rows.push_back({x.x(), x.y()});
  }
  const std::string pts = write("uv.csv", core::format_csv({"u", "v"}, rows));
  const auto r =
      run_cli("calib backproject --calib " + path("c1.yml") + " --points " + pts +
              " --plane 0,0,1,0 --out " + path("xyz.csv") + " --json " + path("bp.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  core::CsvReadOptions o;
  o.exact_columns = {"X", "Y", "Z"};
  const core::CsvTable t = core::read_csv(path("xyz.csv"), o);
  ASSERT_EQ(t.rows.size(), 20u);
  for (size_t i = 0; i < 20; ++i) {
    EXPECT_LT((Eigen::Vector3d(t.at(i, 0), t.at(i, 1), t.at(i, 2)) - world[i]).norm(), 1e-9);
  }
  expect_schema_valid("calib_backproject.schema.json", path("bp.json"));

  const std::string args = "calib backproject --calib " + path("c1.yml") + " --points " + pts +
                           " --out " + path("o.csv") + " --plane ";
  expect_error(run_cli(args + "0,0,1"), {"--plane: expected nx,ny,nz,kappa"});
  expect_error(run_cli(args + "0,0,0,1"), {"--plane", "normal"});
  expect_error(run_cli(args + "0,0,1,nan"), {"--plane"});
  // A plane above the camera: these pixels look down, so it lies behind them.
  expect_error(run_cli(args + "0,0,1,2"), {pts + ":2: back-projection:", "behind"});
}

TEST_F(CalibCliStereo, UncertaintyMap) {
  const auto r = run_cli("calib uncertainty --calib1 " + path("c1.yml") + " --calib2 " +
                         path("c2.yml") + " --z 0.1 --x-range -0.6,0.6 --y-range -0.8,1.2" +
                         " --cells 80 --out " + path("map.png") + " --json " + path("u.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat img = cv::imread(path("map.png"));
  EXPECT_FALSE(img.empty());
  const core::Json j = core::read_json(path("u.json"));
  EXPECT_EQ(j["slice"]["axis"], "z");
  EXPECT_GT(j["summary"]["valid_cells"].get<int>(), 100);
  EXPECT_GT(j["summary"]["min_sigma"].get<double>(), 0.0);  // mm
  expect_schema_valid("calib_uncertainty.schema.json", path("u.json"));

  const std::string args = "calib uncertainty --calib1 " + path("c1.yml") + " --calib2 " +
                           path("c2.yml") + " --out " + path("m.png");
  expect_error(run_cli(args + " --z 0 --y 1"), {"one of --x, --y, --z"});
  expect_error(run_cli(args + " --z-range 0,1"), {"--z-range"});
  expect_error(run_cli(args + " --x-range 1,0"), {"--x-range"});
  expect_error(run_cli(args + " --z 50"), {"no cell"});
  expect_error(run_cli("calib uncertainty --calib1 " + path("c1.yml") + " --calib2 " +
                       path("c2.yml") + " --out " + path("m.jpg")),
               {".png"});
}

TEST_F(CalibCli, StereoOnOpenCVSamples) {
  const auto r = run_cli("calib stereo --out " + path("stereo") + " --json " + path("s.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("13 used"), std::string::npos) << r.out;
  for (const char* f : {"left.yml", "right.yml", "corners.csv"}) {
    EXPECT_TRUE(fs::exists(dir_ / "stereo" / f)) << f;
  }
  const core::Json j = core::read_json(path("s.json"));
  EXPECT_LT(j["neighbour_error"].get<double>(), 0.01);
  EXPECT_LT(j["max_diff_opencv"].get<double>(), 1e-9);
  expect_schema_valid("calib_stereo.schema.json", path("s.json"));

  // The calibration it wrote triangulates its own corners again.
  const std::string corners = path("stereo/corners.csv");
  const core::CsvTable t = core::read_csv(corners);
  std::vector<std::vector<std::optional<double>>> rows;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    rows.push_back({t.at(i, 2), t.at(i, 3), t.at(i, 4), t.at(i, 5)});
  }
  const std::string uv = write("uv.csv", core::format_csv({"u1", "v1", "u2", "v2"}, rows));
  const auto tri =
      run_cli("calib triangulate --calib1 " + path("stereo/left.yml") + " --calib2 " +
              path("stereo/right.yml") + " --points " + uv + " --out " + path("xyz.csv"));
  ASSERT_EQ(tri.code, 0) << tri.err;
  const core::CsvTable xyz = core::read_csv(path("xyz.csv"));
  ASSERT_EQ(xyz.rows.size(), t.rows.size());
  for (size_t i = 0; i < t.rows.size(); i += 37) {
    for (size_t k = 0; k < 3; ++k) EXPECT_NEAR(xyz.at(i, k), t.at(i, 6 + k), 1e-6);
  }

  expect_error(run_cli("calib stereo --images " + path("none") + " --out " + path("o")),
               {path("none") + ": no such directory"});
  expect_error(run_cli("calib stereo --board 9by6 --out " + path("o")), {"--board"});
  expect_error(run_cli("calib stereo --images " + dir_.string() + " --out " + path("o")),
               {dir_.string() + ": no leftNN/rightNN image pairs"});
}

}  // namespace
}  // namespace proprio
