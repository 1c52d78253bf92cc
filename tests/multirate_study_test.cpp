// Multirate methods in a study: a scene that gives the soil's cut its own
// window (scenes/soil.toml: ss_macro_step = 5e-4, 5 H) is studied with every
// lagged method of a case with that cut once more with the cut at 5 H, at
// every H of the sweep (the slow window sweeps beside the fast
// one); the single-rate methods of those cases run the cut at H whatever the
// scene's default. A [coupling] table setting anything else is refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "process_support.hpp"
#include "scene.hpp"
#include "study/study.hpp"
#include "study/study_plan.hpp"
#include "test_support.hpp"

namespace railcosim::multirate_study_test {
namespace {

namespace fs = std::filesystem;

study::StudyPlan soil_plan(const fs::path& dir, const std::string& extra) {
  fs::create_directories(dir);
  std::string scene = test::read_file(test::source_path("scenes/soil.toml"));
  scene.replace(scene.find("end_time = 0.25"), 15, "end_time = 0.02");
  std::ofstream(dir / "soil.toml") << scene << extra;
  study::StudyOptions o;
  o.out = dir / "out";
  o.macro_steps = {1e-4, 5e-4};
  o.transport = "inproc";
  return study::make_plan((dir / "soil.toml").string(), o);
}

TEST(MultirateStudy, TheSoilsWindowIsAMethodAtEveryMacroStep) {
  const fs::path dir =
      fs::temp_directory_path() / ("railcosim_mr_study_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const study::StudyPlan plan = soil_plan(dir, "");
  int multi = 0, single = 0;
  for (const study::PlannedRun& r : plan.runs) {
    const std::string line = study::command_line(plan, r);
    if (r.case_name != "wr-xx+ss-xt-jacobi") continue;
    const std::string H = r.macro_step == 1e-4 ? "0.0001" : "0.0005";
    const std::string slow = r.macro_step == 1e-4 ? "0.0005" : "0.0025";
    if (r.method == "wr-xx+ss-xt-jacobi+ss-at-5H") {
      ++multi;
      EXPECT_NE(line.find(" --macro-step ss=" + slow), std::string::npos) << line;
      EXPECT_NE(r.folder.find("ss-at-5H/wr-xx+ss-xt-jacobi"), std::string::npos) << r.folder;
    } else if (r.method == "wr-xx+ss-xt-jacobi") {
      ++single;
      EXPECT_NE(line.find(" --macro-step ss=" + H), std::string::npos) << line;
    }
  }
  EXPECT_EQ(multi, 2);  // the case and the sweep's other H
  EXPECT_EQ(single, 2);
  // A case of the ss cut alone has its multirate method too (the vehicle
  // and the track at H); a case without the cut has none, and no window.
  int alone = 0;
  for (const study::PlannedRun& r : plan.runs) {
    if (r.method == "ss-xt-jacobi+ss-at-5H" && r.macro_step == 1e-4) {
      ++alone;
      EXPECT_NE(study::command_line(plan, r).find("--macro-step ss=0.0005"), std::string::npos);
    }
    if (r.case_name == "wr-xx-jacobi") {
      EXPECT_EQ(study::command_line(plan, r).find("--macro-step ss"), std::string::npos);
    }
  }
  EXPECT_EQ(alone, 1);
  fs::remove_all(dir);
}

// The study runs what it names: its multirate run's own summary.json has the
// soil's cut at 5 H and the soil's micro steps of that window, and its
// errors are not the single-rate run's.
TEST(MultirateStudy, TheMultirateRunHasItsWindowAndItsOwnErrors) {
  const fs::path dir =
      fs::temp_directory_path() / ("railcosim_mr_runs_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string scene = test::read_file(test::source_path("scenes/soil.toml"));
  scene.replace(scene.find("end_time = 0.25"), 15, "end_time = 0.02");
  std::ofstream(dir / "soil.toml") << scene;
  study::StudyOptions o;
  o.out = dir / "out";
  o.macro_steps = {1e-4};
  o.tolerances = {1e-7};
  o.transport = "inproc";
  o.cases = {"ss-xt-jacobi"};
  o.restart_check = false;
  try {
    study::run_study((dir / "soil.toml").string(), o);
  } catch (const std::exception& e) {
    // The report may fail without its figures; the runs are what is read.
    std::printf("study: %s\n", e.what());
  }
  const fs::path single = o.out / "ss-xt-jacobi" / "summary.json";
  fs::path multi;
  for (const auto& e : fs::recursive_directory_iterator(o.out))
    if (e.path().filename() == "summary.json" &&
        e.path().string().find("ss-at-5H/ss-xt-jacobi") != std::string::npos)
      multi = e.path();
  ASSERT_TRUE(fs::exists(single)) << single;
  ASSERT_FALSE(multi.empty()) << "no ss-at-5H run in " << o.out;
  const std::string one = test::read_file(single.string()), five = test::read_file(multi.string());
  EXPECT_NE(one.find("\"windows\": {\"ss\": 0.0001}"), std::string::npos) << one;
  EXPECT_NE(five.find("\"windows\": {\"ss\": 0.0005}"), std::string::npos) << five;
  auto number = [](const std::string& text, const std::string& key) {
    const std::size_t at = text.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(text.substr(at + key.size() + 4));
  };
  EXPECT_GT(number(five, "rel_l2_error"), 0);
  EXPECT_NE(number(five, "rel_l2_error"), number(one, "rel_l2_error"));
  // The slow participant (the soil, s2) takes a fifth of the macro steps'
  // micro steps at one micro step per window.
  EXPECT_LT(number(five, "s2"), number(one, "s2")) << five;
  fs::remove_all(dir);
}

TEST(MultirateStudy, ACouplingTableSettingMoreThanWindowsIsRefused) {
  const fs::path dir =
      fs::temp_directory_path() / ("railcosim_mr_refuse_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::string scene = test::read_file(test::source_path("scenes/soil.toml"));
  scene.replace(scene.find("ss_macro_step = 5e-4"), 20,
                "ss_macro_step = 5e-4\ninputs = \"linear\"");
  fs::create_directories(dir);
  std::ofstream(dir / "soil.toml") << scene;
  study::StudyOptions o;
  o.out = dir / "out";
  try {
    study::make_plan((dir / "soil.toml").string(), o);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("the cuts' windows, CUT_macro_step, may stay"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace railcosim::multirate_study_test
