// A scene's [coupling] table under `master run`'s flags: its defaults and
// ranges are the flags', its keys stand in for the flags not given, a flag
// given wins, and a study refuses such a scene.
#include "cli/scene_coupling.hpp"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_run.hpp"
#include "process_support.hpp"
#include "run_args_support.hpp"
#include "scene.hpp"
#include "scene_keys.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;

using Parsed = test::ParsedRun;

double fallback(const char* key) {
  return default_number(scene_key("coupling", key));
}
std::string word(const char* key) {
  return scene_key("coupling", key).default_text;
}

TEST(SceneCoupling, TheTablesDefaultsAreTheFlagsDefaults) {
  const Parsed p("");
  const cli::RunArgs& a = p.args;
  EXPECT_EQ(a.coupling, fallback("implicit") != 0.0 ? "implicit" : "explicit");
  EXPECT_EQ(a.inputs, word("inputs"));
  EXPECT_EQ(a.accelerator, word("accelerator"));
  EXPECT_EQ(a.c.accelerator.relaxation, fallback("relaxation"));
  EXPECT_EQ(a.c.max_iterations, fallback("max_iterations"));
  EXPECT_EQ(a.c.convergence, fallback("convergence"));
  EXPECT_EQ(a.c.accelerator.windows_reused, fallback("reused_windows"));
  EXPECT_EQ(a.feedthrough, word("feedthrough"));
  EXPECT_EQ(a.data_plane, word("data_plane"));
  EXPECT_EQ(a.window_steps, fallback("window_steps"));
  EXPECT_EQ(a.step_budget, fallback("step_budget"));
  EXPECT_EQ(a.judge, word("judge"));
  EXPECT_EQ(a.judge_budget, fallback("judge_budget"));
}

// Each number's range in the table is its flag's: both ends accepted, a
// value beyond either refused.
TEST(SceneCoupling, TheTablesRangesAreTheFlagsRanges) {
  const std::pair<const char*, const char*> keys[] = {
      {"relaxation", "--relaxation"},     {"max_iterations", "--max-iterations"},
      {"convergence", "--convergence"},   {"reused_windows", "--reused-windows"},
      {"window_steps", "--window-steps"}, {"step_budget", "--step-budget"}};
  for (const auto& [key, flag] : keys) {
    const KeyRange& r = scene_key("coupling", key).range;
    ASSERT_FALSE(r.lo_open || r.hi_open) << key;
    const bool whole = scene_key("coupling", key).type == KeyType::integer;
    auto value = [whole](double v) {
      return whole ? std::to_string(static_cast<long>(v)) : key_number_text(v);
    };
    EXPECT_NO_THROW(Parsed(std::string(flag) + " " + value(r.lo))) << flag;
    EXPECT_NO_THROW(Parsed(std::string(flag) + " " + value(r.hi))) << flag;
    const double below = whole ? r.lo - 1 : r.lo / 2, above = whole ? r.hi + 1 : r.hi * 2;
    EXPECT_THROW(Parsed(std::string(flag) + " " + value(below)), CLI::ParseError) << flag;
    EXPECT_THROW(Parsed(std::string(flag) + " " + value(above)), CLI::ParseError) << flag;
    EXPECT_NE(r.error(below), "") << key;
    EXPECT_NE(r.error(above), "") << key;
  }
  // judge_budget starts at 0 (no bound), which halving cannot pass below.
  const KeyRange& j = scene_key("coupling", "judge_budget").range;
  EXPECT_EQ(j.lo, 0);
  EXPECT_EQ(j.hi, 1000);
  EXPECT_NO_THROW(Parsed("--judge-budget 0"));
  EXPECT_NO_THROW(Parsed("--judge-budget 1000"));
  EXPECT_THROW(Parsed("--judge-budget -1"), CLI::ParseError);
  EXPECT_THROW(Parsed("--judge-budget 2000"), CLI::ParseError);
  EXPECT_NE(j.error(-1), "");
  EXPECT_NE(j.error(2000), "");
}

// The paper's scene over 0.02 s, without and with a [coupling] table.
std::string paper_short() {
  std::string text = test::read_file(test::source_path("scenes/paper.toml"));
  text.replace(text.find("end_time = 0.25"), 15, "end_time = 0.02");
  return text;
}
std::string paper_with(const std::string& coupling) {
  return paper_short() + "\n[coupling]\n" + coupling;
}

const char* const kEveryKey =
    "implicit = true\ninputs = \"linear\"\naccelerator = \"aitken\"\nrelaxation = 0.25\n"
    "max_iterations = 12\nconvergence = 1e-6\nreused_windows = 3\nfeedthrough = \"resolved\"\n"
    "data_plane = \"relay\"\nwindow_steps = 40\nstep_budget = 90\njudge = \"stability\"\n"
    "judge_budget = 3\n";

TEST(SceneCoupling, TheSceneStandsInForTheFlagsNotGiven) {
  const Scene scene = parse_scene(paper_with(kEveryKey), "coupling.toml");
  ASSERT_TRUE(scene.coupling.given);
  const Parsed p("--inputs hold --max-iterations 7 --data-plane direct");
  const cli::RunArgs a = cli::with_scene_coupling(p.args, scene);
  EXPECT_EQ(a.coupling, "implicit");
  EXPECT_EQ(a.inputs, "hold");  // the flag
  EXPECT_EQ(a.accelerator, "aitken");
  EXPECT_EQ(a.c.accelerator.relaxation, 0.25);
  EXPECT_EQ(a.c.max_iterations, 7);  // the flag
  EXPECT_EQ(a.c.convergence, 1e-6);
  EXPECT_EQ(a.c.accelerator.windows_reused, 3);
  EXPECT_EQ(a.feedthrough, "resolved");
  EXPECT_EQ(a.data_plane, "direct");  // the flag
  EXPECT_EQ(a.window_steps, 40);
  EXPECT_EQ(a.step_budget, 90);
  EXPECT_EQ(a.judge, "stability");
  EXPECT_EQ(a.judge_budget, 3);
  EXPECT_EQ(cli::scene_coupling_note(p.args, scene),
            "; the scene's [coupling] (coupling.toml) set: implicit = true, accelerator = "
            "\"aitken\", relaxation = 0.25, convergence = 1e-06, reused_windows = 3, "
            "feedthrough = \"resolved\", window_steps = 40, step_budget = 90, judge = "
            "\"stability\", judge_budget = 3");
  EXPECT_EQ(cli::with_scene_coupling(Parsed("--judge none").args, scene).judge, "none");
  // `implicit = false` is explicit coupling, even against a default.
  const Parsed q("");
  EXPECT_EQ(
      cli::with_scene_coupling(q.args, parse_scene(paper_with("implicit = false\n"), "e.toml"))
          .coupling,
      "explicit");
}

TEST(SceneCoupling, ASceneWithoutTheTableChangesNothing) {
  const Scene scene = test::paper_scene();
  EXPECT_FALSE(scene.coupling.given);
  const Parsed p("--inputs linear --relaxation 0.3");
  const cli::RunArgs a = cli::with_scene_coupling(p.args, scene);
  EXPECT_EQ(a.coupling, p.args.coupling);
  EXPECT_EQ(a.inputs, "linear");
  EXPECT_EQ(a.accelerator, p.args.accelerator);
  EXPECT_EQ(a.c.accelerator.relaxation, 0.3);
  EXPECT_EQ(a.c.max_iterations, p.args.c.max_iterations);
  EXPECT_EQ(a.c.convergence, p.args.c.convergence);
  EXPECT_EQ(a.c.accelerator.windows_reused, p.args.c.accelerator.windows_reused);
  EXPECT_EQ(a.feedthrough, p.args.feedthrough);
  EXPECT_EQ(a.data_plane, p.args.data_plane);
  EXPECT_EQ(a.window_steps, p.args.window_steps);
  EXPECT_EQ(a.step_budget, p.args.step_budget);
  EXPECT_EQ(cli::scene_coupling_note(p.args, scene), "");
}

TEST(SceneCoupling, BadValuesNameTheKey) {
  auto error_of = [](const std::string& coupling) -> std::string {
    try {
      parse_scene(paper_with(coupling), "bad.toml");
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error_of("inputs = \"cubic\"\n"),
            "bad.toml: key 'coupling.inputs': unknown input mode 'cubic' (known: hold, linear, "
            "extrapolate1, extrapolate2, waveform0, waveform1, waveform2, waveform3)");
  EXPECT_EQ(error_of("max_iterations = 0\n"),
            "bad.toml: key 'coupling.max_iterations': must lie between 1 and 10000");
  EXPECT_EQ(error_of("implicit = \"yes\"\n"),
            "bad.toml: key 'coupling.implicit': must be true or false");
  EXPECT_EQ(error_of("schedule = \"jacobi\"\n"), "bad.toml: key 'coupling.schedule': unknown key");
}

// The real program: a scene with `inputs = "linear"` runs like
// `--inputs linear`, and `--inputs hold` overrides the table.
TEST(SceneCoupling, MasterRunTakesTheTableAndTheFlagWins) {
  const fs::path out = test::temp_dir("scene_coupling");
  std::ofstream(out / "plain.toml") << paper_short();
  std::ofstream(out / "linear.toml") << paper_with("inputs = \"linear\"\n");
  auto history = [&](const std::string& scene, const std::string& flags, const std::string& tag) {
    const test::Outcome o = test::run_master(
        "run --scene " + (out / scene).string() +
        " --case wr-xx-gauss-seidel --transport inproc --out " + (out / tag).string() + flags);
    EXPECT_EQ(o.status, 0) << o.output;
    return test::read_file(out / tag / "wr-xx-gauss-seidel" / "history.csv");
  };
  const std::string hold = history("plain.toml", "", "hold");
  const std::string flag_linear = history("plain.toml", " --inputs linear", "flag_linear");
  const std::string table_linear = history("linear.toml", "", "table_linear");
  const std::string flag_wins = history("linear.toml", " --inputs hold", "flag_wins");
  ASSERT_GT(hold.size(), 1000u);
  EXPECT_NE(hold, flag_linear) << "linear inputs must change a Gauss-Seidel run";
  EXPECT_EQ(table_linear, flag_linear);
  EXPECT_EQ(flag_wins, hold);
  EXPECT_NE(test::read_file(out / "table_linear" / "wr-xx-gauss-seidel" / "summary.json")
                .find("\"inputs\": \"linear\""),
            std::string::npos);
  fs::remove_all(out);
}

TEST(SceneCoupling, ErrorsSayWhatTheTableSetAndAStudyRefusesIt) {
  const fs::path out = test::temp_dir("scene_coupling_errors");
  const fs::path scene = out / "implicit.toml";
  std::ofstream(scene) << paper_with("implicit = true\ninputs = \"extrapolate1\"\n");
  const test::Outcome o =
      test::run_master("run --scene " + scene.string() +
                       " --case wr-xx-jacobi --transport inproc --out " + (out / "res").string());
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("--inputs extrapolate1 applies to explicit coupling"), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("the scene's [coupling] (" + scene.string() +
                          ") set: implicit = true, inputs = \"extrapolate1\""),
            std::string::npos)
      << o.output;
  const test::Outcome s =
      test::run_master("study --scene " + scene.string() + " --out " + (out / "study").string());
  EXPECT_EQ(s.status, 2) << s.output;
  EXPECT_NE(s.output.find(scene.string() + ": the scene's [coupling] table sets how master run"),
            std::string::npos)
      << s.output;
  fs::remove_all(out);
}

}  // namespace
}  // namespace railcosim
