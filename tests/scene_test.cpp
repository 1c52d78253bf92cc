#include "scene.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "cosim_case.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

std::string paper_text() {
  std::ifstream in(test::source_path("scenes/paper.toml"));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces the first line that starts with `prefix` by `line`.
std::string with_line(const std::string& prefix, const std::string& line) {
  std::string text = paper_text();
  const std::size_t at = text.find("\n" + prefix);
  EXPECT_NE(at, std::string::npos) << prefix;
  if (at == std::string::npos) return text;
  const std::size_t end = text.find('\n', at + 1);
  return text.substr(0, at + 1) + line + text.substr(end);
}

// Parses `text` and returns the SceneError message ("" if none).
std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "bad.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, PaperSceneHoldsTheModelTable) {
  const Scene s = test::paper_scene();
  EXPECT_EQ(s.vehicle_mass, 11250.0);
  EXPECT_DOUBLE_EQ(s.load(), 110362.5);
  EXPECT_EQ(s.hertz_constant, 92.86e9);
  EXPECT_EQ(s.young_modulus, 210e9);
  EXPECT_EQ(s.second_moment, 1987e-8);
  EXPECT_EQ(s.area, 63.8e-4);
  EXPECT_EQ(s.density, 7850.0);
  EXPECT_EQ(s.sleeper_mass, 90.84);
  EXPECT_EQ(s.sleeper_spacing, 0.6);
  EXPECT_EQ(s.pad_stiffness, 180e6);
  EXPECT_EQ(s.pad_damping, 28e3);
  EXPECT_EQ(s.ballast_stiffness, 25.5e6);
  EXPECT_EQ(s.ballast_damping, 40e3);
  EXPECT_EQ(s.sleeper_count, 50);
  EXPECT_EQ(s.elements_per_span, 2);
  EXPECT_DOUBLE_EQ(s.speed, 300.0 / 3.6);
  EXPECT_EQ(s.initial_position, 2.0);
  EXPECT_EQ(s.macro_step, 1e-4);
  EXPECT_EQ(s.end_time, 0.25);
  EXPECT_EQ(s.gravity, 9.81);
  EXPECT_EQ(s.rail_nodes(), 101);
  EXPECT_EQ(s.macro_steps(), 2500);
}

struct BadCase {
  const char* label;
  const char* key;      // start of the line to replace
  const char* line;     // its replacement ("" drops it)
  const char* message;  // expected in the error, with the key
};

class BadSceneTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadSceneTest, StopsWithAMessageNamingTheKey) {
  const BadCase& c = GetParam();
  const std::string msg = error_of(with_line(c.key, c.line));
  EXPECT_NE(msg.find("bad.toml"), std::string::npos) << msg;
  EXPECT_NE(msg.find(c.message), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadSceneTest,
    ::testing::Values(
        BadCase{"missing_key", "density =", "", "'rail.density': missing"},
        BadCase{"unknown_key", "density =", "density = 7850.0\ndensty = 1.0",
                "'rail.densty': unknown key"},
        BadCase{"negative_mass", "mass =", "mass = -11250.0", "'vehicle.mass': must be positive"},
        BadCase{"zero_stiffness", "stiffness =", "stiffness = 0",
                "'railpad.stiffness': must be positive"},
        BadCase{"negative_sleeper_mass", "mass = 90.84", "mass = -1.0",
                "'sleepers.mass': must be positive"},
        BadCase{"odd_elements_per_span", "elements_per_span =", "elements_per_span = 3",
                "'rail.elements_per_span': must be a positive even number"},
        BadCase{"load_starts_outside", "initial_position =", "initial_position = -1.0",
                "'vehicle.initial_position': the load starts at x = -1"},
        BadCase{"load_runs_off_the_rail", "end_time =", "end_time = 0.5",
                "'simulation.end_time': the load reaches x = 43.6"},
        BadCase{"wrong_type", "count =", "count = \"fifty\"",
                "'sleepers.count': must be a whole number of sleepers or \"auto\""},
        BadCase{"fractional_count", "count =", "count = 50.5",
                "'sleepers.count': must be an integer"},
        BadCase{"unknown_soil", "model =", "model = \"elastic\"",
                "'soil.model': unknown soil model"}),
    [](const auto& param_info) { return std::string(param_info.param.label); });

TEST(Scene, UnknownTableIsRejected) {
  const std::string msg = error_of(paper_text() + "\n[wheels]\nmass = 1.0\n");
  EXPECT_NE(msg.find("'wheels': unknown table"), std::string::npos) << msg;
}

TEST(Scene, SyntaxErrorNamesFileAndLine) {
  const std::string msg = error_of("[rail\n");
  EXPECT_NE(msg.find("bad.toml:1:"), std::string::npos) << msg;
}

TEST(Scene, MissingFileIsNamed) {
  try {
    load_scene("no/such/scene.toml");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("no/such/scene.toml"), std::string::npos);
  }
}

// The canonical text: parsing it gives the same scene and the same text
// (what a node gets is what the master runs), for every shipped scene.
TEST(SceneText, EveryShippedSceneReadsBackFromItsText) {
  for (const char* file :
       {"paper", "soil", "car_irregular", "freight160", "wheel_flat", "ground_vibration"}) {
    const Scene s = load_scene(test::source_path(std::string("scenes/") + file + ".toml"));
    const Scene again = parse_scene(s.text, s.source, &s.files);
    EXPECT_TRUE(again == s) << file;
    EXPECT_EQ(again.text, s.text) << file;
    EXPECT_NO_THROW(check_scene_text(s)) << file;
  }
}

TEST(SceneText, EditsGoThroughTheParserAndCanBeTakenBack) {
  const Scene s = test::paper_scene();
  const Scene fixed = with_keys(s, {{"simulation.micro_steps", 4}, {"vehicle.speed_kmh", 72.0}});
  EXPECT_EQ(fixed.micro_steps, 4);
  EXPECT_EQ(fixed.speed, 20.0);
  EXPECT_NO_THROW(check_scene_text(fixed));
  const Scene back = with_keys(fixed, {{"simulation.micro_steps", kLeftOut}});
  EXPECT_EQ(back.micro_steps, 0);
  EXPECT_EQ(back.speed, 20.0);
  try {
    with_keys(s, {{"sleepers.mass", -1.0}});
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'sleepers.mass'"), std::string::npos) << e.what();
  }
  Scene changed = s;
  changed.speed = 1.0;
  EXPECT_THROW(check_scene_text(changed), std::logic_error);
}

// The editor under with_keys and the study's --sweep: any depth, tables made
// on the way, and a path through a value named.
TEST(SceneText, TheEditorMakesTablesAndNamesAPathThroughAValue) {
  const std::string text = "[scene]\nname = \"x\"\n";
  EXPECT_EQ(edit_scene_text(text, "t.toml", {{"a.b.c", 2}, {"scene.name", kLeftOut}}),
            "[a.b]\nc = 2\n\n[scene]");
  try {
    edit_scene_text(text, "t.toml", {{"scene.name.x", 1.0}});
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "scene key 'scene.name.x': name is not a table");
  }
}

// [vehicle.fmu]: the vehicle participant is an FMU; its table is handed on
// whole (it goes into the node's own configuration and the fingerprint),
// only wheel/rail cases remain and there is no monolithic one.
TEST(Scene, AVehicleFmuTableIsHandedOnWholeAndLeavesOnlyWheelRailCases) {
  const Scene s = parse_scene(paper_text() +
                                  "\n[vehicle.fmu]\nfile = \"vehicle.fmu\"\n"
                                  "wr_in_displacement = \"u\"\n",
                              "vfmu.toml");
  EXPECT_TRUE(s.outside_vehicle());
  EXPECT_TRUE(s.outside_model());
  EXPECT_NE(s.fmu_mapping("vehicle").find("wr_in_displacement = 'u'"), std::string::npos)
      << s.fmu_mapping("vehicle");
  EXPECT_EQ(s.fmu_mapping("soil"), "");
  for (const std::string& name : case_names(s)) EXPECT_EQ(name.rfind("wr-", 0), 0u) << name;
  EXPECT_THROW(check_case_for_scene(parse_case("monolithic"), s), std::invalid_argument);
  EXPECT_THROW(check_case_for_scene(parse_case("rs-xx-jacobi"), s), std::invalid_argument);
  EXPECT_NO_THROW(check_case_for_scene(parse_case("wr-xx-jacobi"), s));
  EXPECT_NE(error_of(paper_text() + "\n[vehicle]\nfmu = 3\n"), "");
  const std::string not_table = error_of(with_line("mass = 11250.0", "mass = 11250.0\nfmu = 3"));
  EXPECT_NE(not_table.find("key 'vehicle.fmu': must be a table ([vehicle.fmu])"), std::string::npos)
      << not_table;
  const Scene plain = parse_scene(paper_text(), "paper.toml");
  EXPECT_FALSE(plain.outside_vehicle());
  EXPECT_EQ(plain.fmu_mapping("vehicle"), "");
}

}  // namespace
}  // namespace railcosim
