// Every numeric value of the paper scene, mutated to the values that broke
// the loader before (0, negative, huge, subnormal, integers beyond int,
// nan/inf, wrong types): each mutant either loads, and then its model takes
// finite steps, or is refused with a message naming the file and a key —
// never bad_alloc, "not positive definite", or a message without a key.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "monolithic.hpp"
#include "scene.hpp"
#include "scene_checks.hpp"
#include "test_support.hpp"
#include "wire.hpp"

namespace railcosim {
namespace scene_mutation_test {

const std::vector<std::string> kMutations = {
    "0",   "-1",  "-0.5", "1e308", "5e-324", "4294967346", "-4294967296", "9223372036854775807",
    "nan", "inf", "-inf", "1e-30", "1e30",   "\"text\"",   "true",        "[1.0]"};

std::string paper_text() {
  std::ifstream in(test::source_path("scenes/paper.toml"));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Mutant {
  std::string key, value, text;
};

// One mutant per numeric key of the file and mutation.
std::vector<Mutant> mutants() {
  const std::string text = paper_text();
  const std::regex table(R"(^\s*\[(\w+)\]\s*$)");
  const std::regex number(R"(^(\s*(\w+)\s*=\s*)([-+0-9.eE]+)(.*)$)");
  std::vector<Mutant> out;
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::string current;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (std::regex_match(lines[i], m, table)) current = m[1];
    if (!std::regex_match(lines[i], m, number)) continue;
    for (const std::string& v : kMutations) {
      std::string mutated;
      for (std::size_t j = 0; j < lines.size(); ++j)
        mutated += (j == i ? m[1].str() + v + m[4].str() : lines[j]) + "\n";
      out.push_back({current + "." + m[2].str(), v, mutated});
    }
  }
  return out;
}

TEST(SceneMutation, EveryMutantLoadsAndRunsOrNamesFileAndKey) {
  const std::vector<Mutant> all = mutants();
  ASSERT_GT(all.size(), 20 * kMutations.size());  // every numeric key of the file
  int loaded = 0, refused = 0;
  for (const Mutant& m : all) {
    SCOPED_TRACE(m.key + " = " + m.value);
    Scene scene;
    try {
      scene = parse_scene(m.text, "mutated.toml");
    } catch (const SceneError& e) {
      ++refused;
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("mutated.toml", 0), 0u) << msg;
      EXPECT_NE(msg.find("key '"), std::string::npos) << msg;
      continue;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a scene error: " << e.what();
      continue;
    }
    ++loaded;
    // What loads must be something the model can compute with: a few
    // macro steps of the monolithic model from its static state, finite.
    // (Meshes beyond a few thousand DOFs are left out to keep this fast.)
    if (scene.rail_nodes() > 2000) continue;
    try {
      MonolithicModel model(scene, scene.macro_step, scene.tolerance);
      for (long n = 0; n < 3; ++n) model.advance(n);
      for (double w : model.rail_deflection()) ASSERT_TRUE(std::isfinite(w));
      ASSERT_TRUE(std::isfinite(model.history_row(3).contact_force));
    } catch (const StepFailure&) {
      // A scene whose solution runs away is a result (diverged), not a crash.
    } catch (const std::exception& e) {
      ADD_FAILURE() << "loaded, then: " << e.what();
    }
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(refused, 0);
}

// The integer of a key is range-checked before it becomes an int: 2^32 + 50
// sleepers is an error, not 50 sleepers.
TEST(SceneMutation, IntegersDoNotWrap) {
  std::string text = paper_text();
  text = std::regex_replace(text, std::regex(R"(count = 50 )"), "count = 4294967346 ");
  try {
    parse_scene(text, "wrap.toml");
    FAIL() << "4294967346 sleepers loaded";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("wrap.toml: key 'sleepers.count': out of range"),
              std::string::npos)
        << e.what();
  }
}

// Values that pass each key's own check but make the model's arithmetic
// give NaN are refused with the file and key, on the file path and over the
// wire alike.
TEST(SceneMutation, ValuesThatWouldGiveNanAreRefusedWithTheirKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"vehicle.mass", "5e-324"},
      {"simulation.gravity", "1e308"},
      {"ballast.damping", "inf"},
  };
  for (const auto& [key, value] : cases) {
    const std::string table = key.substr(0, key.find('.'));
    const std::string name = key.substr(key.find('.') + 1);
    std::string text = paper_text();
    // Replace the key's value inside its table.
    const auto at = text.find("\n" + name + " = ", text.find("[" + table + "]"));
    ASSERT_NE(at, std::string::npos) << key;
    const auto start = text.find('=', at) + 2;
    text.replace(start, text.find(' ', start) - start, value);
    try {
      parse_scene(text, "nan.toml");
      ADD_FAILURE() << key << " = " << value << " loaded";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("nan.toml: key '" + key + "'"), std::string::npos)
          << e.what();
    }
    // The same text sent to a node as the scene of its Configure.
    wire::Configure configure;
    configure.set_scene(text);
    try {
      scene_from_wire(configure);
      ADD_FAILURE() << key << " = " << value << " accepted over the wire";
    } catch (const ProtocolError& e) {
      EXPECT_EQ(e.code(), wire::Error::BAD_SCENE);
      EXPECT_NE(std::string(e.what()).find("key '" + key + "'"), std::string::npos) << e.what();
    }
  }
}

// The nodes' mesh limits hold for the master too, before it computes the
// monolithic reference.
TEST(SceneMutation, MeshLimitsApplyOnLoading) {
  std::string text = paper_text();
  text = std::regex_replace(text, std::regex(R"(count = 50 )"), "count = 20001 ");
  text = std::regex_replace(text, std::regex(R"(end_time = 0.25 )"), "end_time = 0.01 ");
  try {
    parse_scene(text, "big.toml");
    FAIL() << "20001 sleepers loaded";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("big.toml: key 'sleepers.count': 20001 sleepers exceed"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace scene_mutation_test
}  // namespace railcosim
