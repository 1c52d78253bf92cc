// The scene key table against the parser: every key the parser reads has an
// entry (a lookup without one is a std::logic_error), every entry is reached
// by some scene, and the defaults, ranges and choice errors the parser
// applies are the table's.
#include "scene_keys.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `text` with the first line that starts with `prefix` replaced by `line`.
std::string replace_line(std::string text, const std::string& prefix, const std::string& line) {
  const std::size_t at = text.find("\n" + prefix);
  if (at == std::string::npos) throw std::runtime_error("no line starts with " + prefix);
  const std::size_t end = text.find('\n', at + 1);
  return text.substr(0, at + 1) + line + text.substr(end);
}

// Scenes that reach the keys the shipped scenes leave out: every model of
// [irregularity], a flat on the car's third wheel, the optional keys of
// [sleepers] and [simulation], an outside soil, every key of [coupling], a
// train (every key of [[vehicle.cars]]), both resilient layers.
std::vector<std::pair<std::string, std::string>> variants() {
  const std::string paper = read_text(test::source_path("scenes/paper.toml"));
  const std::string car = read_text(test::source_path("scenes/car_irregular.toml"));
  std::string sim = replace_line(paper, "count =", "count = 50\nlength = 2.5");
  sim = replace_line(sim, "tolerance =", "tolerance = 1e-7\nrestart = \"carry\"\nmicro_steps = 4");
  sim += "\n[output]\nballast_forces = false\n";
  return {
      {"sim", sim},
      {"sine", paper + "\n[irregularity]\nmodel = \"sine\"\namplitude = 0.001\n"
                       "wavelength = 2.0\nphase_deg = 30\n"},
      {"random", paper + "\n[irregularity]\nmodel = \"random\"\na_v = 0.5\nomega_c = 0.8\n"
                         "wavelength_min = 2.0\nwavelength_max = 30.0\nseed = 7\n"
                         "amplitude_scale = 0.5\ncomponents = 64\ngrid_step = 0.05\n"},
      {"dipped", paper + "\n[irregularity]\nmodel = \"dipped_joint\"\nposition = 10.0\n"
                         "length = 0.4\ndepth = 0.002\n"},
      {"csv", paper + "\n[irregularity]\nmodel = \"csv\"\nfile = \"profile.csv\"\n"},
      {"external", replace_line(paper, "model = \"fixed\"", "model = \"external\"\nlayers = 3")},
      {"coupling", paper + "\n[coupling]\nimplicit = true\ninputs = \"linear\"\n"
                           "accelerator = \"aitken\"\nrelaxation = 0.25\nmax_iterations = 12\n"
                           "convergence = 1e-6\nreused_windows = 3\nfeedthrough = \"lagged\"\n"
                           "data_plane = \"relay\"\nwindow_steps = 40\n"},
      {"train", read_text(test::source_path("tests/train_scene.toml"))},
      {"layers", replace_line(paper, "damping = 40e3", "damping = 40e3\nmass = 300.0") +
                     "\n[under_sleeper_pads]\nstiffness = 1e8\nloss_factor = 0.2\narea = 0.1\n"
                     "reference_frequency = 40\n\n[under_ballast_mats]\nstiffness = 1e7\n"
                     "loss_factor = 0.2\narea = 1.05\n"},
      {"car_flat", car + "\n[wheel_flat]\nlength = 0.05\nwheel_diameter = 0.92\nwheel = 3\n"
                         "shape = \"rounded\"\nangle_deg = 10\n"},
  };
}

class SceneKeysTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rc_scene_keys_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "profile.csv") << "x_m,r_m\n0,0\n15,0.001\n30,0\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Parses `text` as a file in the temporary folder; returns the keys it read.
  std::set<std::string> keys_read(const std::string& name, const std::string& text) {
    SceneKeyTrace trace;
    parse_scene(text, (dir_ / (name + ".toml")).string());
    return trace.keys();
  }
  fs::path dir_;
};

TEST_F(SceneKeysTest, EveryEntryIsReachedAndEveryKeyReadHasOne) {
  std::set<std::string> reached;
  std::vector<std::string> scenes;
  for (const auto& f : fs::directory_iterator(test::source_path("scenes")))
    if (f.path().extension() == ".toml") scenes.push_back(f.path().string());
  ASSERT_GE(scenes.size(), 7u);
  for (const std::string& path : scenes) {
    SceneKeyTrace trace;
    // A lookup without an entry throws std::logic_error, which fails here.
    EXPECT_NO_THROW(load_scene(path)) << path;
    reached.insert(trace.keys().begin(), trace.keys().end());
  }
  for (const auto& [name, text] : variants()) {
    std::set<std::string> keys;
    EXPECT_NO_THROW(keys = keys_read(name, text)) << name;
    reached.insert(keys.begin(), keys.end());
  }
  std::set<std::string> tables;
  for (const std::string& k : reached) tables.insert(k.substr(0, k.rfind('.')));
  for (const SceneKey& k : scene_keys()) {
    if (!tables.count(k.table)) continue;
    EXPECT_TRUE(reached.count(k.table + "." + k.key))
        << k.table << "." << k.key << " has an entry that no scene reaches";
  }
  EXPECT_EQ(tables.size(), scene_key_tables().size());
}

TEST(SceneKeys, ALookupWithoutAnEntryIsAProgrammingError) {
  EXPECT_THROW(scene_key("rail", "poisson"), std::logic_error);
  try {
    scene_key("rail", "poisson");
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'rail.poisson'"), std::string::npos) << e.what();
  }
  // A required key, or one whose default the parser computes, has no
  // default to take as it is.
  EXPECT_THROW(default_number(scene_key("rail", "density")), std::logic_error);
  EXPECT_THROW(default_number(scene_key("irregularity", "grid_step")), std::logic_error);
}

TEST(SceneKeys, EntriesAreUniqueAndComplete) {
  std::set<std::string> seen;
  for (const SceneKey& k : scene_keys()) {
    EXPECT_TRUE(seen.insert(k.table + "." + k.key).second) << k.table << "." << k.key;
    EXPECT_FALSE(k.meaning.empty()) << k.key;
    if (k.type == KeyType::choice) {
      EXPECT_GE(k.choices.size(), 2u) << k.key;
      EXPECT_FALSE(k.required) << k.key;
    }
    if (!k.required && k.type != KeyType::table) {
      EXPECT_TRUE(!std::isnan(k.default_number) || !k.default_text.empty()) << k.key;
    }
    if (!k.required && !std::isnan(k.default_number)) {
      EXPECT_EQ(k.range.error(k.default_number), "") << k.key << ": default out of range";
    }
  }
}

// What the parser takes for a key left out is the entry's default.
TEST_F(SceneKeysTest, LeftOutKeysTakeTheTablesDefaults) {
  const std::string paper = read_text(test::source_path("scenes/paper.toml"));
  std::string bare = paper.substr(0, paper.find("[cosim]"));
  bare = replace_line(bare, "name =", "");
  const Scene s = parse_scene(bare, (dir_ / "bare.toml").string());
  EXPECT_EQ(s.divergence_factor, default_number(scene_key("cosim", "divergence_factor")));
  EXPECT_EQ(s.amplification_threshold,
            default_number(scene_key("cosim", "amplification_threshold")));
  EXPECT_EQ(s.sleeper_length, default_number(scene_key("sleepers", "length")));
  EXPECT_FALSE(s.sleeper_length_given);
  EXPECT_EQ(s.ballast_forces, default_number(scene_key("output", "ballast_forces")) != 0.0);
  EXPECT_EQ(s.name, scene_key("scene", "name").default_text);
  EXPECT_EQ(s.restart, scene_key("simulation", "restart").default_text);
  EXPECT_EQ(s.micro_steps, 0);  // "adaptive"

  const Scene r = parse_scene(paper +
                                  "\n[irregularity]\nmodel = \"random\"\nfra_class = 5\n"
                                  "wavelength_min = 2.0\nwavelength_max = 30.0\nseed = 1\n",
                              (dir_ / "random.toml").string());
  EXPECT_EQ(r.irregularity.random.components,
            default_number(scene_key("irregularity", "components")));
  EXPECT_EQ(r.irregularity.random.amplitude_scale,
            default_number(scene_key("irregularity", "amplitude_scale")));
  EXPECT_EQ(r.irregularity.random.grid_step, 2.0 / 20.0);  // "wavelength_min / 20"
  EXPECT_EQ(parse_scene(read_text(test::source_path("scenes/wheel_flat.toml")),
                        (dir_ / "flat.toml").string())
                .wheel_flat->wheel,
            static_cast<int>(default_number(scene_key("wheel_flat", "wheel"))) - 1);
}

// The table's ranges and choices give the parser's error texts.
TEST(SceneKeys, RangesAndChoicesGiveTheParsersErrors) {
  EXPECT_EQ(scene_key("rail", "density").range.error(-7850), "must be positive (got -7850)");
  EXPECT_EQ(scene_key("railpad", "damping").range.error(-1), "must be zero or positive (got -1)");
  EXPECT_EQ(scene_key("railpad", "damping").range.error(0), "");
  EXPECT_EQ(scene_key("sleepers", "length").range.error(12),
            "must lie in (0, 10] m (got 12.000000)");
  EXPECT_EQ(scene_key("sleepers", "length").range.error(10), "");
  EXPECT_EQ(scene_key("sleepers", "margin_tolerance").range.error(1),
            "must lie strictly between 0 and 1");
  EXPECT_EQ(scene_key("simulation", "micro_steps").range.error(65537),
            "must lie between 1 and 65536, or be left out (adaptive)");
  EXPECT_EQ(scene_key("sleepers", "length").range.text(), "(0, 10]");
  EXPECT_EQ(scene_key("rail", "density").range.text(), "> 0");
  EXPECT_EQ(scene_key("railpad", "damping").range.text(), "≥ 0");
  EXPECT_EQ(scene_key("irregularity", "fra_class").range.text(), "1 … 6");
  EXPECT_EQ(choice_error(scene_key("vehicle", "model"), "tram"),
            "unknown vehicle model 'tram' (known: wheel, quarter, car, train)");
  EXPECT_EQ(choice_error(scene_key("simulation", "restart"), "keep"),
            "must be \"consistent\" or \"carry\" (got \"keep\")");
  EXPECT_EQ(choice_error(scene_key("soil", "model"), "fe"), "");
  EXPECT_EQ(choice_error(scene_key("soil", "model"), "green"), "");
}

TEST_F(SceneKeysTest, TheParserAppliesTheTablesRangesAsItReads) {
  const std::string paper = read_text(test::source_path("scenes/paper.toml"));
  auto error_of = [&](const std::string& text) -> std::string {
    try {
      parse_scene(text, "bad.toml");
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of(replace_line(paper, "count =", "count = 50\nlength = 12")),
            "bad.toml: key 'sleepers.length': must lie in (0, 10] m (got 12.000000)");
  EXPECT_EQ(error_of(replace_line(paper, "tolerance =", "tolerance = 1e-7\nrestart = \"keep\"")),
            "bad.toml: key 'simulation.restart': must be \"consistent\" or \"carry\" (got "
            "\"keep\")");
  EXPECT_EQ(error_of(paper + "\n[irregularity]\nmodel = \"random\"\nfra_class = 7\n"),
            "bad.toml: key 'irregularity.fra_class': must be an FRA track class 1 to 6");
  EXPECT_EQ(error_of(replace_line(paper, "model = \"fixed\"", "model = \"fe\"\nranks = 0")),
            "bad.toml: key 'soil.ranks': must be a whole number from 1 to 256 (the MPI ranks "
            "of the FE soil)");
}

}  // namespace
}  // namespace railcosim
