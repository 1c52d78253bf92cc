// A macro step per cut: --macro-step CUT=H_cut and the scene's [coupling]
// CUT_macro_step are read, checked against the finest window (an integer
// multiple of it, the nearest multiples named otherwise) and, as long as the
// plan runs every cut at the finest window, a coarser one is refused by name
// rather than run at a window other than the one asked for.
#include "engine/cut_windows.hpp"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>

#include "cli/cli_run.hpp"
#include "cli/scene_coupling.hpp"
#include "cosim_case.hpp"
#include "process_support.hpp"
#include "run_args_support.hpp"
#include "scene.hpp"
#include "scene_error.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace cut_windows_test {

// The message of what `f` throws as std::invalid_argument, "" if nothing.
template <class F>
std::string refusal(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

using Parsed = test::ParsedRun;

Scene paper_with(const std::string& coupling) {
  std::string text = test::read_file(test::source_path("scenes/paper.toml"));
  return parse_scene(text + "\n[coupling]\n" + coupling, "multirate.toml");
}

TEST(CutWindows, MacroStepValuesAreTheFinestWindowOrACutsWindow) {
  std::map<std::string, engine::CutWindow> cuts;
  EXPECT_EQ(engine::read_macro_step("1e-4", cuts), 1e-4);
  EXPECT_EQ(engine::read_macro_step("ss=1e-3", cuts), 0.0);
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_EQ(cuts.at("ss").window, 1e-3);
  EXPECT_EQ(cuts.at("ss").origin, "--macro-step ss=1e-3");
  EXPECT_EQ(refusal([&] { engine::read_macro_step("ss=2e-3", cuts); }),
            "--macro-step ss=2e-3: cut ss was already given (--macro-step ss=1e-3)");
  EXPECT_EQ(refusal([&] { engine::read_macro_step("xx=1e-3", cuts); }),
            "--macro-step xx=1e-3: unknown cut 'xx' (the cuts are wr, rs and ss)");
  for (const char* bad : {"wr=-1e-3", "wr=0", "wr=", "wr=1e-3s", "abc", "inf"})
    EXPECT_NE(refusal([&] { engine::read_macro_step(bad, cuts); }), "") << bad;
}

TEST(CutWindows, AWindowIsAnIntegerMultipleOfTheFinestOrNamesTheNearest) {
  const auto given = [](double w) {
    return std::map<std::string, engine::CutWindow>{
        {"ss", {.window = w, .origin = "[coupling] ss_macro_step in s.toml"}}};
  };
  EXPECT_EQ(engine::cut_ratios(1e-4, given(1e-3)).at("ss"), 10);
  EXPECT_EQ(engine::cut_ratios(0.1, given(0.3)).at("ss"), 3);  // 0.3 / 0.1 is 2.9999999999999996
  EXPECT_EQ(engine::cut_ratios(1e-4, given(1e-4)).at("ss"), 1);
  EXPECT_EQ(engine::cut_ratios(2.5e-5, given(1e-3)).at("ss"), 40);
  EXPECT_EQ(refusal([&] { engine::cut_ratios(1e-4, given(1.05e-3)); }),
            "[coupling] ss_macro_step in s.toml: the window 0.00105 s of cut ss is not an "
            "integer multiple of the finest window 0.0001 s; the nearest multiples are 0.001 s "
            "and 0.0011 s");
  EXPECT_EQ(refusal([&] { engine::cut_ratios(1e-4, given(5e-5)); }),
            "[coupling] ss_macro_step in s.toml: the window 5e-05 s of cut ss is not an "
            "integer multiple of the finest window 0.0001 s; the nearest multiples are 0.0001 s");
}

TEST(CutWindows, TheCommandLineTakesRepeatedMacroSteps) {
  const Parsed p("--macro-step 5e-5 --macro-step wr=1e-4");
  EXPECT_EQ(p.args.macro_step, 5e-5);
  ASSERT_EQ(p.args.cut_windows.count("wr"), 1u);
  EXPECT_EQ(p.args.cut_windows.at("wr").window, 1e-4);
  EXPECT_THROW(Parsed("--macro-step wr=1.5s"), CLI::ParseError);
  EXPECT_THROW(Parsed("--macro-step ss=1e-3 --macro-step ss=1e-3"), CLI::ParseError);
}

TEST(CutWindows, TheSceneGivesACutItsWindowAndTheFlagWins) {
  const Scene scene = paper_with("wr_macro_step = 1e-3\n");
  ASSERT_EQ(scene.coupling.wr_macro_step, 1e-3);
  const CaseSpec spec = parse_case("wr-xx-gauss-seidel");
  // A default applies where the case has the cut (the vehicle stays at H).
  EXPECT_EQ(cli::check_cut_windows(Parsed("").args, scene, spec, 1e-4),
            (std::map<std::string, long>{{"wr", 10}}));
  // Where the case has a finer cut, it applies; where it is no multiple of
  // H over one, or for a cut the case lacks, it does not.
  const CaseSpec two = parse_case("wr-xx+rs-xx-gauss-seidel");
  EXPECT_EQ(cli::check_cut_windows(Parsed("").args, scene, two, 1e-4),
            (std::map<std::string, long>{{"rs", 1}, {"wr", 10}}));
  EXPECT_EQ(cli::check_cut_windows(Parsed("").args, scene, two, 3e-4),
            (std::map<std::string, long>{{"rs", 1}, {"wr", 1}}));
  EXPECT_EQ(
      cli::check_cut_windows(Parsed("").args, paper_with("ss_macro_step = 1e-3\n"), two, 1e-4),
      (std::map<std::string, long>{{"rs", 1}, {"wr", 1}}));
  const std::map<std::string, long> ratios =
      cli::check_cut_windows(Parsed("--macro-step wr=1e-4").args, scene, spec, 1e-4);
  EXPECT_EQ(ratios, (std::map<std::string, long>{{"wr", 1}}));
  EXPECT_EQ(refusal([&] {
              cli::check_cut_windows(Parsed("--macro-step ss=1e-4").args, test::paper_scene(), spec,
                                     1e-4);
            }),
            "--macro-step ss=1e-4: case wr-xx-gauss-seidel has no cut ss");
  EXPECT_THROW(paper_with("ss_macro_step = -1\n"), SceneError);
}

}  // namespace cut_windows_test
}  // namespace railcosim
