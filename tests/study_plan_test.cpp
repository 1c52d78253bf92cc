// A study as a plan: `master study --plan`, GNU parallel, `master study
// --collect`, against `master study` itself; a plan with a run missing; a
// sweep over the vehicle's speed. A short paper scene in-process keeps it
// cheap.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "process_support.hpp"
#include "scene.hpp"
#include "study/study.hpp"
#include "study/study_plan.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace study_plan_test {

using test::read_file;
using test::split_csv;

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string output;
};

// Runs a shell command in the test's folder; its exit status and output.
Result sh(const fs::path& dir, const std::string& cmd) {
  Result r;
  FILE* p = popen(("cd '" + dir.string() + "' && " + cmd + " 2>&1").c_str(), "r");
  std::array<char, 4096> buf{};
  while (p && fgets(buf.data(), buf.size(), p)) r.output += buf.data();
  const int st = p ? pclose(p) : -1;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

using Row = std::map<std::string, std::string>;

std::vector<Row> read_csv(const fs::path& file) {
  std::istringstream in(read_file(file));
  std::string line;
  std::getline(in, line);
  const auto header = split_csv(line);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    const auto f = split_csv(line);
    Row r;
    for (std::size_t i = 0; i < header.size() && i < f.size(); ++i) r[header[i]] = f[i];
    rows.push_back(r);
  }
  return rows;
}

// The verdict lines of REPORT.md: "| claim | **verdict** |".
std::vector<std::string> verdicts(const std::string& report) {
  std::vector<std::string> out;
  // | conclusion | paper | ours | judged with | **verdict** |
  const std::regex re(R"(^\| ([^|]+) \|.*\| \*\*([^*]+)\*\* \|$)");
  std::istringstream in(report);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, re)) out.push_back(m[1].str() + ": " + m[2].str());
  }
  return out;
}

const std::string kMaster = std::string(RAILCOSIM_BIN_DIR) + "/master";
const std::string kSettings = " --macro-steps 1e-4,5e-4 --tolerances 1e-6 --transport inproc";

class StudyPlanTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("railcosim_plan_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::string scene = read_file(test::source_path("scenes/paper.toml"));
    scene.replace(scene.find("end_time = 0.25"), 15, "end_time = 0.02");
    std::ofstream(dir_ / "short.toml") << scene;
    local_ = sh(dir_, kMaster + " study --scene short.toml --out local --jobs 2" + kSettings);
    plan_ =
        sh(dir_, kMaster + " study --scene short.toml --out planned --plan plan.txt" + kSettings);
    parallel_ = sh(dir_, "parallel --jobs 2 < plan.txt");
    first_collect_ = sh(dir_, kMaster + " study --collect planned");
    parallel2_ = sh(dir_, "parallel --jobs 1 < planned/plan-2.txt");
    collect_ = sh(dir_, kMaster + " study --collect planned");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static inline fs::path dir_;
  static inline Result local_, plan_, parallel_, first_collect_, parallel2_, collect_;
};

TEST_F(StudyPlanTest, PlanRunWithParallelCollectsToTheLocalStudy) {
  ASSERT_EQ(local_.status, 0) << local_.output;
  ASSERT_EQ(plan_.status, 0) << plan_.output;
  ASSERT_EQ(parallel_.status, 0) << parallel_.output;
  // Stage 1 collected: stage 2 is planned and not run yet.
  EXPECT_EQ(first_collect_.status, 3) << first_collect_.output;
  ASSERT_EQ(parallel2_.status, 0) << parallel2_.output;
  ASSERT_EQ(collect_.status, 0) << collect_.output;

  const auto a = read_csv(dir_ / "local" / "summary.csv");
  const auto b = read_csv(dir_ / "planned" / "summary.csv");
  std::vector<Row> a1, b1;
  for (const auto& r : a)
    if (r.at("group") != "other-transport") a1.push_back(r);
  for (const auto& r : b)
    if (r.at("group") != "other-transport") b1.push_back(r);
  ASSERT_EQ(a1.size(), b1.size());
  ASSERT_GT(a1.size(), 30u);
  for (std::size_t i = 0; i < a1.size(); ++i) {
    ASSERT_EQ(a1[i].size(), b1[i].size());
    for (const auto& [k, v] : a1[i])
      if (k != "wall_s") {
        EXPECT_EQ(v, b1[i].at(k)) << a1[i].at("folder") << ": " << k;
      }
  }
  // Stage 2 picks the cheapest by wall time, which differs between the two:
  // each rerun is the same run as its stage-1 row over the other transport,
  // so it has the same error.
  for (const auto* rows : {&a, &b}) {
    int reruns = 0;
    for (const auto& r : *rows) {
      if (r.at("group") != "other-transport") continue;
      ++reruns;
      EXPECT_EQ(r.at("transport"), "tcp");
      bool found = false;
      for (const auto& s : *rows)
        found = found || (s.at("group") != "other-transport" && s.at("method") == r.at("method") &&
                          s.at("macro_step_s") == r.at("macro_step_s") &&
                          s.at("rel_l2_error") == r.at("rel_l2_error"));
      EXPECT_TRUE(found) << r.at("folder");
    }
    EXPECT_GE(reruns, 1);
    EXPECT_LE(reruns, 3);
  }
  const auto va = verdicts(read_file(dir_ / "local" / "REPORT.md"));
  EXPECT_GE(va.size(), 9u);
  EXPECT_EQ(va, verdicts(read_file(dir_ / "planned" / "REPORT.md")));
}

TEST_F(StudyPlanTest, EveryRunKindIsACompleteCommandThatReadsBack) {
  ASSERT_EQ(plan_.status, 0) << plan_.output;
  const std::string text = read_file(dir_ / "plan.txt");
  EXPECT_EQ(text, read_file(dir_ / "planned" / "plan.txt"));
  EXPECT_NE(text.find("#% format = 1\n"), std::string::npos);
  for (const char* kind :
       {"group=case", "group=sweep", "group=tolerance", "group=restart", "group=converged",
        "--coupling implicit --inputs linear --accelerator iqn-ils", "--inputs extrapolate1",
        "--coupling implicit --inputs waveform3 --accelerator iqn-ils", "--feedthrough resolved",
        "restart/carry/scene.toml"})
    EXPECT_NE(text.find(kind), std::string::npos) << kind;
  {  // Substep waveforms travel in process only: their runs are over inproc.
    std::istringstream lines(text);
    int waveform = 0;
    for (std::string line; std::getline(lines, line);)
      if (line.find("--inputs waveform3") != std::string::npos) {
        ++waveform;
        EXPECT_NE(line.find("--transport inproc"), std::string::npos) << line;
      }
    EXPECT_GE(waveform, 4);
  }
  const Scene carry = load_scene((dir_ / "planned" / "restart" / "carry" / "scene.toml").string());
  EXPECT_EQ(carry.micro_steps, 10);
  EXPECT_EQ(carry.restart, "carry");
  // Read back and written again: the same command lines.
  study::StudyPlan p = study::read_plan(dir_ / "plan.txt");
  std::istringstream in(text);
  std::size_t k = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    ASSERT_LT(k, p.runs.size());
    EXPECT_EQ(line.substr(0, line.find(" #% ")), study::command_line(p, p.runs[k])) << line;
    ++k;
  }
  EXPECT_EQ(k, p.runs.size());
}

TEST_F(StudyPlanTest, AMissingRunIsNamedAndTheExitStatusSaysSo) {
  ASSERT_EQ(collect_.status, 0) << collect_.output;
  const fs::path copy = dir_ / "gathered";
  fs::copy(dir_ / "planned", copy, fs::copy_options::recursive);
  fs::remove_all(copy / "sweep" / "H_0.0005" / "rs-xx-jacobi");
  const Result r =
      sh(dir_, "RAILCOSIM_FIGURES=/nonexistent " + kMaster + " study --collect gathered");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("sweep/H_0.0005/rs-xx-jacobi missing"), std::string::npos) << r.output;
  const std::string report = read_file(copy / "REPORT.md");
  EXPECT_NE(report.find("## Incomplete study"), std::string::npos);
  EXPECT_NE(report.find("| sweep/H_0.0005/rs-xx-jacobi | missing |"), std::string::npos);
  for (const auto& row : read_csv(copy / "summary.csv"))
    if (row.at("folder") == "sweep/H_0.0005/rs-xx-jacobi") {
      EXPECT_EQ(row.at("status"), "missing");
    }
}

// A run's message is one cell of REPORT.md's table, whole: a '|' it holds
// (a norm) is escaped, not the end of the cell.
TEST_F(StudyPlanTest, ARunsMessageStaysInOneCellOfTheReport) {
  ASSERT_EQ(collect_.status, 0) << collect_.output;
  const fs::path copy = dir_ / "piped";
  fs::copy(dir_ / "planned", copy, fs::copy_options::recursive);
  const fs::path json = copy / "sweep" / "H_0.0005" / "rs-xx-jacobi" / "summary.json";
  std::string text = read_file(json);
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"\"status\": \"ok\"", "\"status\": \"failed\""},
        {"\"message\": \"\"", "\"message\": \"the residual ||G(x) - x|| grew\""}}) {
    ASSERT_NE(text.find(from), std::string::npos) << text;
    text.replace(text.find(from), from.size(), to);
  }
  std::ofstream(json) << text;
  const Result r = sh(dir_, "RAILCOSIM_FIGURES=/nonexistent " + kMaster + " study --collect piped");
  EXPECT_EQ(r.status, 1) << r.output;
  const std::string report = read_file(copy / "REPORT.md");
  EXPECT_NE(
      report.find("| sweep/H_0.0005/rs-xx-jacobi | failed | the residual \\|\\|G(x) - x\\|\\| "
                  "grew |\n"),
      std::string::npos)
      << report;
}

TEST(StudySweep, OneSceneVariantPerSpeedAndTheReportGroupsByIt) {
  const fs::path dir =
      fs::temp_directory_path() / ("railcosim_sweep_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string scene = read_file(test::source_path("scenes/paper.toml"));
  scene.replace(scene.find("end_time = 0.25"), 15, "end_time = 0.01");
  std::ofstream(dir / "short.toml") << scene;
  const std::string common =
      " study --scene short.toml --out swept --macro-steps 1e-4 --tolerances "
      "1e-6 --transport inproc";
  const Result bad = sh(dir, kMaster + common + " --sweep vehicle.speed_kmhh=200 --plan p.txt");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("vehicle.speed_kmhh"), std::string::npos) << bad.output;
  const Result r = sh(dir, "RAILCOSIM_FIGURES=/nonexistent " + kMaster + common +
                               " --jobs 2 --sweep vehicle.speed_kmh=200,300");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string report = read_file(dir / "swept" / "REPORT.md");
  std::size_t last = 0;
  for (const char* v : {"200", "300"}) {
    const fs::path vdir = dir / "swept" / (std::string("vehicle.speed_kmh_") + v);
    const Scene s = load_scene((vdir / "scene.toml").string());
    // km/h to m/s and back: within a few ulps.
    EXPECT_NEAR(s.speed * 3.6, std::stod(v), 1e-9);
    EXPECT_TRUE(fs::exists(vdir / "wr-xx-jacobi" / "summary.json"));
    EXPECT_TRUE(fs::exists(vdir / "summary.csv"));
    const std::size_t at = report.find(std::string("## vehicle.speed_kmh=") + v + "\n");
    ASSERT_NE(at, std::string::npos) << v;
    EXPECT_GT(at, last);  // in the sweep's order
    EXPECT_NE(report.find("### The paper's conclusions", at), std::string::npos);
    last = at;
  }
  std::map<std::string, int> per_variant;
  // Stage 2 reruns the cheapest per variant, which may be 1 to 3 runs: not counted.
  for (const auto& row : read_csv(dir / "swept" / "summary.csv"))
    if (row.at("group") != "other-transport") ++per_variant[row.at("variant")];
  ASSERT_EQ(per_variant.size(), 2u);
  EXPECT_EQ(per_variant["vehicle.speed_kmh=200"], per_variant["vehicle.speed_kmh=300"]);
  fs::remove_all(dir);
}

}  // namespace study_plan_test
}  // namespace railcosim
