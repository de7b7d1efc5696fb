// Scene files in JSON and YAML: one tree, one reader, errors with file and line.
#include "proprio/sim/scene_file.hpp"

#include <gtest/gtest.h>

#include "../support/paths.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/scene_builder.hpp"
#include "proprio/sim/world.hpp"
#include "sim_test_util.hpp"

namespace proprio::sim {
namespace {
namespace fs = std::filesystem;

const fs::path kScenarios = proprio::test::data_dir() / "scenarios";

std::string error_of(const fs::path& file) {
  try {
    (void)read_scene_file(file);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SceneFile, TheSameSceneInYamlAndJsonGivesTheSameDescription) {
  const ObjectCatalogue catalogue = ObjectCatalogue::load_default();
  const fs::path json = kScenarios / "crate_and_mug.json";
  const fs::path yaml = kScenarios / "crate_and_mug.yaml";
  EXPECT_EQ(read_scene_file(yaml), read_scene_file(json));
  RecordOptions o;
  o.scenario = json.string();
  const ScenarioPlan from_json = plan_scenario(o, catalogue);
  o.scenario = yaml.string();
  const ScenarioPlan from_yaml = plan_scenario(o, catalogue);
  EXPECT_EQ(from_yaml.target, "crate");
  EXPECT_EQ(from_yaml.target, from_json.target);
  EXPECT_EQ(from_yaml.push_start, from_json.push_start);
  EXPECT_EQ(from_yaml.push_end, from_json.push_end);
  ASSERT_EQ(from_yaml.scene.objects.size(), 3U);
  EXPECT_EQ(build_scene(from_yaml.scene, catalogue).xml,
            build_scene(from_json.scene, catalogue).xml);
}

TEST(SceneFile, YamlScalarsBecomeJsonScalars) {
  const fs::path f = test::temp_dir() / "scalars.yaml";
  core::write_file_atomic(f,
                          "i: 3\nd: -0.25\nb: true\nn: ~\ne:\ns: mug\nq: \"3\"\nl: [1, 2.5, x]\n");
  const core::Json j = read_scene_file(f);
  EXPECT_TRUE(j["i"].is_number_integer());
  EXPECT_EQ(j["i"], 3);
  EXPECT_EQ(j["d"], -0.25);
  EXPECT_EQ(j["b"], true);
  EXPECT_TRUE(j["n"].is_null());
  EXPECT_TRUE(j["e"].is_null());
  EXPECT_EQ(j["s"], "mug");
  EXPECT_EQ(j["q"], "3");  // quoted: a string
  EXPECT_EQ(j["l"], core::Json::parse(R"([1, 2.5, "x"])"));
}

// Issue 16: a 1 KB scene of nested aliases expanded past 4 GB (then was accepted or aborted on
// std::bad_alloc); deep nesting overflowed yaml-cpp's recursion.
TEST(SceneFile, NestedAliasesAndDeepNestingAreRefused) {
  const fs::path f = test::temp_dir() / "laughs.yaml";
  // Nine levels of ten aliases each: 10^10 values once expanded. Built by appends (GCC 12's
  // -Wrestrict misfires on long chains of +).
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 10; ++i) {
    const std::string p = "*a" + std::to_string(i - 1);
    text += "a";
    text += std::to_string(i);
    text += ": &a";
    text += std::to_string(i);
    text += " [";
    for (int k = 0; k < 10; ++k) {
      if (k > 0) text += ", ";
      text += p;
    }
    text += "]\n";
  }
  core::write_file_atomic(f, text);
  std::string m = error_of(f);
  EXPECT_NE(m.find("laughs.yaml:"), std::string::npos) << m;
  EXPECT_NE(m.find("the aliases expand to too many values"), std::string::npos) << m;
  // A few aliases within the budget still work.
  core::write_file_atomic(f, "base: &b {x: 1, y: 2}\nfirst: *b\nsecond: *b\n");
  EXPECT_EQ(read_scene_file(f)["second"]["y"], 2);
  // Found by fuzz_scene: a byte that is not UTF-8 became a JSON string that failed when written.
  core::write_file_atomic(f, "base: &b {x: 1, \xff\xff: 2}\n");
  m = error_of(f);
  EXPECT_NE(m.find("laughs.yaml:1: not UTF-8 text"), std::string::npos) << m;
  // Found by fuzz_scene: yaml-cpp turned this valid UTF-8 into a value that is not.
  core::write_file_atomic(f, std::string("base: \x15\0N4YAML9ExceptionE2}\nftypt: \nb\n", 38));
  EXPECT_NE(error_of(f).find("laughs.yaml:"), std::string::npos) << error_of(f);
  core::write_file_atomic(f, "deep: " + std::string(50000, '[') + "\n");
  m = error_of(f);
  EXPECT_NE(m.find("laughs.yaml:1: nested deeper than 64 levels"), std::string::npos) << m;
}

TEST(SceneFile, BadYamlNamesTheFileAndLine) {
  const fs::path f = test::temp_dir() / "bad.yaml";
  core::write_file_atomic(f, "objects:\n  - type: mug\n    x: [0.2, \n");
  std::string m = error_of(f);
  EXPECT_NE(m.find("bad.yaml:"), std::string::npos) << m;
  core::write_file_atomic(f, "objects:\n  - type: mug\n    x: 0.2\n    x: 0.3\ntarget: mug\n");
  m = error_of(f);
  EXPECT_NE(m.find("bad.yaml:4: duplicate key 'x'"), std::string::npos) << m;
  core::write_file_atomic(f, "objects:\n  - type: mug\n    x: .nan\n");
  m = error_of(f);
  EXPECT_NE(m.find("bad.yaml:3: '.nan' is not a finite number"), std::string::npos) << m;
  core::write_file_atomic(f, "- just\n- a list\n");
  m = error_of(f);
  EXPECT_NE(m.find("bad.yaml: a scene file holds a map"), std::string::npos) << m;
  m = error_of(test::temp_dir() / "missing.yaml");
  EXPECT_NE(m.find("missing.yaml: no such file"), std::string::npos) << m;
  m = error_of(test::temp_dir() / "scene.txt");
  EXPECT_NE(m.find("must end in .json, .yaml or .yml"), std::string::npos) << m;
  // A YAML scene that parses but is wrong is refused by the one reader, naming the file.
  core::write_file_atomic(f, "objects: []\ntarget: mug\n");
  RecordOptions o;
  o.scenario = f.string();
  try {
    (void)plan_scenario(o, ObjectCatalogue::load_default());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml: 'objects' must be a non-empty array"),
              std::string::npos)
        << e.what();
  }
}

// Every problem of a scene file names the file (issue 16), also those the catalogue and the
// value readers find: an unknown object type, a missing or mistyped value, a bad shape.
TEST(SceneFile, EveryProblemOfASceneNamesTheFile) {
  const fs::path f = test::temp_dir() / "named_scene.yaml";
  const ObjectCatalogue catalogue = ObjectCatalogue::load_default();
  for (const char* text : {
           "objects:\n  - type: unicorn\n    x: 0.2\n    y: 0\ntarget: unicorn\n",
           "objects:\n  - type: mug\n    y: 0\ntarget: mug\n",
           "objects:\n  - type: mug\n    x: abc\n    y: 0\ntarget: mug\n",
           "objects:\n  - type: mug\n    x: 0.2\n    y: 0\ntarget: 3\n",
           "objects:\n  - name: blob\n    shape: sphere\n    x: 0.2\n    y: 0\ntarget: blob\n",
           "objects:\n  - type: mug\n    x: 0.2\n    y: 0\ntarget: mug\ncamera: 7\n",
       }) {
    core::write_file_atomic(f, text);
    RecordOptions o;
    o.scenario = f.string();
    try {
      (void)plan_scenario(o, catalogue);
      ADD_FAILURE() << "no error: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
  // A scene MuJoCo's compiler refuses (it said "<generated scene>: MuJoCo warns ...").
  core::write_file_atomic(f, "objects:\n  - type: mug\n    x: 1e30\n    y: 0\ntarget: mug\n");
  RecordOptions o;
  o.scenario = f.string();
  try {
    (void)build_scenario_world(plan_scenario(o, catalogue), catalogue, o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(f.string() + ": MuJoCo", 0), 0U) << e.what();
  }
}

}  // namespace
}  // namespace proprio::sim
