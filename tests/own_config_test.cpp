// What an outside participant is told about itself: its own table of the
// scene (the [soil] table of an external soil, any keys, as TOML text inside
// Configure and the fingerprint) and the geometry of its coupling points
// (footprints at the sleepers/soil cut).
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "cosim_case.hpp"
#include "model.hpp"
#include "scene_error.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"
#include "wire.hpp"

namespace railcosim {
namespace {

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The soil scene with its [soil] table replaced by an outside soil's own.
std::string external_soil_scene(const std::string& soil_table) {
  const std::string text = file_text(test::source_path("scenes/soil.toml"));
  const std::regex table(R"(\[soil\][^\[]*)");
  return std::regex_replace(text, table, soil_table + "\n");
}

const char* const kOwnTable = R"([soil]
model = "external"
receivers_m = [4.0, 8.0, 16.0]
[[soil.layers]]
thickness = 3.0
shear_wave_speed = 150.0
[[soil.layers]]
thickness = 20.0
shear_wave_speed = 250.0
)";

SubsystemConfig soil_config(const Scene& scene, const char* case_name) {
  const auto parts = partition(scene, parse_case(case_name));
  SubsystemConfig c;
  c.participant = parts.back();
  c.macro_step = scene.macro_step;
  c.tolerance = scene.tolerance;
  return c;
}

TEST(OwnConfig, AnExternalSoilGetsItsWholeTableInConfigure) {
  const Scene scene = parse_scene(external_soil_scene(kOwnTable), "outside.toml");
  EXPECT_EQ(scene.soil_model, "external");
  const wire::Envelope e = configure_envelope(scene, soil_config(scene, "ss-xx-jacobi"), true);
  ASSERT_EQ(e.configure().participant(), "soil");
  const toml::table own = toml::parse(e.configure().own_config());
  EXPECT_EQ(own["model"].value_or(std::string()), "external");
  EXPECT_EQ(own["receivers_m"][2].value_or(0.0), 16.0);
  EXPECT_EQ(own["layers"][1]["shear_wave_speed"].value_or(0.0), 250.0);
  EXPECT_EQ(scene_from_wire(e.configure()).soil_config, e.configure().own_config());
  // The other participants are told nothing of it.
  const auto parts = partition(scene, parse_case("ss-xx-jacobi"));
  SubsystemConfig track = soil_config(scene, "ss-xx-jacobi");
  track.participant = parts.front();
  EXPECT_EQ(configure_envelope(scene, track, true).configure().own_config(), "");
}

TEST(OwnConfig, TheFingerprintCoversTheOwnTable) {
  const Scene a = parse_scene(external_soil_scene(kOwnTable), "a.toml");
  std::string other = kOwnTable;
  other.replace(other.find("250.0"), 5, "251.0");
  const Scene b = parse_scene(external_soil_scene(other), "b.toml");
  EXPECT_NE(scene_fingerprint(a), scene_fingerprint(b));
  const wire::Envelope e = configure_envelope(a, soil_config(a, "ss-xx-jacobi"), true);
  EXPECT_EQ(scene_fingerprint(scene_from_wire(e.configure())), scene_fingerprint(a));
}

// The FE soil (model = "fe") is an outside participant the master starts:
// its table travels as an external soil's does, and the master reads `ranks`.
TEST(OwnConfig, TheFeSoilGetsItsTableAndItsRanksAreChecked) {
  std::string table = kOwnTable;
  table.replace(table.find("\"external\""), 10, "\"fe\"\nranks = 3");
  const Scene scene = parse_scene(external_soil_scene(table), "fe.toml");
  EXPECT_EQ(scene.soil_model, "fe");
  EXPECT_EQ(scene.soil_ranks, 3);
  EXPECT_TRUE(scene.outside_soil());
  const wire::Envelope e = configure_envelope(scene, soil_config(scene, "ss-xt-jacobi"), true);
  const toml::table own = toml::parse(e.configure().own_config());
  EXPECT_EQ(own["model"].value_or(std::string()), "fe");
  EXPECT_EQ(own["layers"][1]["shear_wave_speed"].value_or(0.0), 250.0);
  EXPECT_EQ(case_names(scene).front(), "ss-xx-jacobi");  // no monolithic, no wr or rs cases
  EXPECT_EQ(load_scene(test::source_path("scenes/ground_vibration.toml")).soil_ranks, 2);
  EXPECT_EQ(load_scene(test::source_path("scenes/ground_vibration_ci.toml")).soil_model, "fe");
  for (const char* bad : {"ranks = 0", "ranks = 2.5", "ranks = \"two\"", "ranks = 1000"}) {
    std::string t = kOwnTable;
    t.replace(t.find("\"external\""), 10, std::string("\"fe\"\n") + bad);
    try {
      parse_scene(external_soil_scene(t), "fe.toml");
      FAIL() << bad << " was accepted";
    } catch (const SceneError& err) {
      EXPECT_NE(std::string(err.what())
                    .find("fe.toml: key 'soil.ranks': must be a whole number "
                          "from 1 to 256"),
                std::string::npos)
          << err.what();
    }
  }
}

// The Green's-function soil (model = "green") is started by the master too,
// from its row of the table of started soils; it takes no MPI ranks, so
// `ranks` is one of its own keys (which it refuses), not the master's.
TEST(OwnConfig, TheGreenSoilIsAStartedSoilFromItsTableRow) {
  std::string table = kOwnTable;
  table.replace(table.find("\"external\""), 10, "\"green\"\nranks = 1000");
  const Scene scene = parse_scene(external_soil_scene(table), "green.toml");
  EXPECT_TRUE(scene.outside_soil());
  ASSERT_NE(scene.started_soil(), nullptr);
  EXPECT_EQ(std::string(scene.started_soil()->module), "green_soil.participant");
  EXPECT_FALSE(scene.started_soil()->mpi);
  EXPECT_EQ(scene.soil_ranks, 1);
  const wire::Envelope e = configure_envelope(scene, soil_config(scene, "ss-xt-jacobi"), true);
  const toml::table own = toml::parse(e.configure().own_config());
  EXPECT_EQ(own["model"].value_or(std::string()), "green");
  EXPECT_EQ(own["ranks"].value_or(0), 1000);
  EXPECT_EQ(case_names(scene).front(), "ss-xx-jacobi");
  EXPECT_EQ(
      load_scene(test::source_path("scenes/ground_vibration_green_ci.toml")).started_soil()->title,
      std::string("the Green's-function soil"));
  EXPECT_EQ(find_outside_soil("lumped"), nullptr);
  EXPECT_EQ(std::string(find_outside_soil("fe")->module), "fe_soil.participant");
}

// The fingerprint of scenes/soil.toml as the master sends it (protocol
// version 3, the FNV-1a of its canonical text): a regression value, which
// moves only when the scene or the canonical form does. A key given with its
// default value is still a change of the text.
TEST(OwnConfig, TheSoilScenesFingerprintStays) {
  EXPECT_EQ(scene_fingerprint(load_scene(test::source_path("scenes/soil.toml"))),
            2719539509589375300ull);
  const Scene s = test::paper_scene();
  EXPECT_NE(scene_fingerprint(with_keys(s, {{"sleepers.length", 2.6}})), scene_fingerprint(s));
}

TEST(Footprints, EverySleeperOfTheSsCutHasItsBayOnTheSoil) {
  const Scene scene = load_scene(test::source_path("scenes/soil.toml"));
  const auto cfg = soil_config(scene, "ss-xt-jacobi");
  const wire::Interface w = to_wire(scene, cfg.participant.interfaces.front());
  ASSERT_EQ(w.cut(), "ss");
  ASSERT_EQ(w.footprints_size(), w.x_size());
  ASSERT_EQ(w.x_size(), scene.sleeper_count);
  for (int i = 0; i < w.x_size(); ++i) {
    const wire::Footprint& f = w.footprints(i);
    EXPECT_EQ(f.x(), w.x(i));
    EXPECT_DOUBLE_EQ(f.length() * f.width(), 0.78);  // 0.6 m x 2.6 m / 2, the scene's A
    EXPECT_DOUBLE_EQ(f.y(), 0.65);
    EXPECT_EQ(f.z(), 0.0);
  }
  // Neighbouring bays tile the track without gap or overlap.
  for (int i = 1; i < w.x_size(); ++i)
    EXPECT_NEAR(w.footprints(i).x() - w.footprints(i - 1).x(), w.footprints(i).length(), 1e-12);
  const Scene paper = test::paper_scene();
  const auto rs = partition(paper, parse_case("rs-xx-jacobi"));
  EXPECT_EQ(to_wire(paper, rs.front().interfaces.front()).footprints_size(), 0);
}

TEST(Footprints, TheSleeperLengthIsAKeyOfTheScene) {
  std::string text = file_text(test::source_path("scenes/soil.toml"));
  const std::string with =
      std::regex_replace(text, std::regex("spacing = 0.6"), "spacing = 0.6\nlength = 2.0");
  const Scene scene = parse_scene(with, "short.toml");
  EXPECT_EQ(footprints(scene, find_cut("ss")).front().width, 1.0);
  const std::string bad =
      std::regex_replace(text, std::regex("spacing = 0.6"), "spacing = 0.6\nlength = -1.0");
  try {
    parse_scene(bad, "bad.toml");
    FAIL() << "a negative sleeper length was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.toml: key 'sleepers.length'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace railcosim
