// A small study end to end, as a user runs it: the master process, nodes over
// TCP, every promised file; summary.csv against the per-run summary.json.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "process_support.hpp"
#include "run/assess.hpp"
#include "run/runner.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace {

using test::read_file;
using test::split_csv;

namespace fs = std::filesystem;

// The text of a scalar in our flat summary.json ("" for null).
std::string json_value(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\": (\"([^\"]*)\"|[^,\\n}]*)");
  std::smatch m;
  if (!std::regex_search(json, m, re)) return "<missing>";
  if (m[2].matched) return m[2];
  return m[1] == "null" ? "" : std::string(m[1]);
}

// The rows of a CSV file, each by column name.
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& file) {
  std::istringstream in(read_file(file));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const auto f = split_csv(line);
    std::map<std::string, std::string> r;
    for (std::size_t i = 0; i < header.size() && i < f.size(); ++i) r[header[i]] = f[i];
    rows.push_back(std::move(r));
  }
  return rows;
}

class StudyTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("railcosim_study_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The paper scene, cut short.
    std::string scene = read_file(test::source_path("scenes/paper.toml"));
    scene.replace(scene.find("end_time = 0.25"), 15, "end_time = 0.02");
    std::ofstream(dir_ / "short.toml") << scene;
    const std::string cmd = std::string(RAILCOSIM_BIN_DIR) + "/master study --scene " +
                            (dir_ / "short.toml").string() + " --out " + (dir_ / "out").string() +
                            " --jobs 2 --macro-steps 1e-4,5e-4 --tolerances 1e-6,1e-8 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::array<char, 4096> buf{};
    while (p && fgets(buf.data(), buf.size(), p)) output_ += buf.data();
    const int st = p ? pclose(p) : -1;
    status_ = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static inline fs::path dir_;
  static inline std::string output_;
  static inline int status_ = -1;
};

TEST_F(StudyTest, FinishesAndWritesEveryPromisedFile) {
  ASSERT_EQ(status_, 0) << output_;
  const fs::path out = dir_ / "out";
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_TRUE(fs::exists(out / "REPORT.md"));
  for (const char* run :
       {"monolithic", "wr-xx-jacobi", "wr-xt-jacobi", "resolved/wr-xt-jacobi", "rs-xt-gauss-seidel",
        "sweep/H_0.0005/rs-xx-jacobi", "sweep/tol_1e-08/monolithic", "converged/monolithic",
        "restart/carry/rs-xx-jacobi"})
    for (const char* file : {"deflection.csv", "history.csv", "summary.json"})
      EXPECT_TRUE(fs::exists(out / run / file)) << run << "/" << file;
  const std::string report = read_file(out / "REPORT.md");
  EXPECT_NE(report.find("## The paper's conclusions"), std::string::npos);
  EXPECT_NE(report.find("## Stability map"), std::string::npos);
  EXPECT_NE(report.find("## Cheapest method per accuracy"), std::string::npos);
  EXPECT_NE(report.find("## Spectra"), std::string::npos);
  EXPECT_NE(report.find("| carry | "), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "implicit-linear-iqn-ils" / "rs-xt-jacobi" / "convergence.csv"));
  // The plan the study ran, and stage 2 (the other-transport reruns).
  EXPECT_TRUE(fs::exists(out / "plan.txt"));
  EXPECT_TRUE(fs::exists(out / "plan-2.txt"));
  EXPECT_TRUE(fs::exists(out / "restart" / "carry" / "scene.toml"));
  // Every case ran, so every conclusion of the paper gets a verdict.
  EXPECT_EQ(report.find("not checked"), std::string::npos) << report.substr(0, 3000);
  for (const char* claim :
       {"abnormally amplified", "divides the error of Jacobi", "Resolved feedthrough reduces"}) {
    EXPECT_NE(report.find(claim), std::string::npos) << claim;
  }
  // Figures, where matplotlib is installed (the install script installs it);
  // otherwise the report must say why there are none.
  if (report.find("Figures were not drawn") == std::string::npos) {
    for (const char* fig :
         {"deflection", "errors", "speed_accuracy", "stability_map", "contact_force", "spectra"}) {
      EXPECT_TRUE(fs::exists(out / "figures" / (std::string(fig) + ".png"))) << fig;
      EXPECT_NE(report.find(std::string("figures/") + fig + ".png"), std::string::npos) << fig;
    }
  }
}

TEST_F(StudyTest, SummaryCsvMatchesEveryRunsSummaryJson) {
  ASSERT_EQ(status_, 0) << output_;
  std::istringstream csv(read_file(dir_ / "out" / "summary.csv"));
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = split_csv(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  std::map<std::string, int> rows;
  while (std::getline(csv, line)) {
    const auto f = split_csv(line);
    ASSERT_EQ(f.size(), header.size()) << line;
    const std::string json = read_file(dir_ / "out" / f[col["folder"]] / "summary.json");
    for (const char* key : {"case", "status", "macro_step_s", "t_end_s", "wall_s", "macro_steps",
                            "max_abs_error_m", "rel_l2_error", "history_error", "transport"})
      EXPECT_EQ(f[col[key]], json_value(json, key)) << f[col["folder"]] << ": " << key;
    if (!f[col["rel_l2_error"]].empty()) {
      EXPECT_GE(std::stod(f[col["rel_l2_error"]]), 0.0);
    }
    ++rows[f[col["group"]]];
  }
  // 10 paper methods, and per Jacobi case of each cut an implicit, an
  // extrapolated and an implicit cubic-waveform one: 22 methods at each of
  // the 2 macro steps; the
  // monolithic case; 2 tolerances; the rail/sleepers pair under 2 restart
  // conventions; the converged reference; the cheapest methods (1 to 3)
  // over the other transport.
  EXPECT_EQ(rows["case"], 23);
  EXPECT_EQ(rows["converged"], 1);
  EXPECT_EQ(rows["sweep"], 22);
  EXPECT_EQ(rows["tolerance"], 2);
  EXPECT_EQ(rows["restart"], 4);
  EXPECT_GE(rows["other-transport"], 1);
  EXPECT_LE(rows["other-transport"], 3);
}

// The cubic-waveform method of every single-cut Jacobi case at both macro
// steps, in process (waveforms do not cross TCP), none of them rerun over TCP.
TEST_F(StudyTest, SummaryCsvHoldsTheWaveformMethodInProcess) {
  ASSERT_EQ(status_, 0) << output_;
  const auto rows = csv_rows(dir_ / "out" / "summary.csv");
  std::map<std::string, int> waveform;
  for (const auto& r : rows) {
    if (r.at("method").find("+implicit-waveform3-iqn-ils") == std::string::npos) continue;
    EXPECT_EQ(r.at("transport"), "inproc") << r.at("folder");
    EXPECT_EQ(r.at("inputs"), "waveform3") << r.at("folder");
    EXPECT_EQ(r.at("coupling_method"), "implicit") << r.at("folder");
    EXPECT_NE(r.at("group"), "other-transport") << r.at("folder");
    ++waveform[r.at("case")];
  }
  for (const char* c : {"wr-xt-jacobi", "wr-xx-jacobi", "rs-xt-jacobi", "rs-xx-jacobi"})
    EXPECT_EQ(waveform[c], 2) << c;
  EXPECT_EQ(waveform.size(), 4u);
  const std::string report = read_file(dir_ / "out" / "REPORT.md");
  EXPECT_NE(report.find("rs cut, in process"), std::string::npos);
  EXPECT_NE(report.find("## Error against H per input degree"), std::string::npos);
}

// error_slopes.csv: per case and inputs, the least-squares slope of
// log(error) on log(H), refitted here from summary.csv.
TEST_F(StudyTest, SlopeTableIsTheFitOfSummaryCsv) {
  ASSERT_EQ(status_, 0) << output_;
  std::map<std::pair<std::string, std::string>, std::vector<std::pair<double, double>>> points;
  for (const auto& r : csv_rows(dir_ / "out" / "summary.csv"))
    if ((r.at("group") == "case" || r.at("group") == "sweep") &&
        r.at("coupling_method") == "implicit" && r.at("accelerator") == "iqn-ils" &&
        !r.at("rel_l2_error_converged").empty() && std::stod(r.at("rel_l2_error_converged")) > 0)
      points[{r.at("case"), r.at("inputs")}].emplace_back(
          std::log(std::stod(r.at("macro_step_s"))),
          std::log(std::stod(r.at("rel_l2_error_converged"))));
  const auto slopes = csv_rows(dir_ / "out" / "error_slopes.csv");
  ASSERT_EQ(slopes.size(), points.size());
  int fitted = 0;
  for (const auto& s : slopes) {
    const auto& p = points.at({s.at("case"), s.at("inputs")});
    ASSERT_EQ(std::to_string(p.size()), s.at("points")) << s.at("case");
    if (p.size() < 2) continue;
    // Two macro steps: the slope is the secant.
    const double secant = (p[1].second - p[0].second) / (p[1].first - p[0].first);
    EXPECT_NEAR(std::stod(s.at("slope")), secant, 1e-9 * (1 + std::abs(secant))) << s.at("case");
    ++fitted;
  }
  EXPECT_GE(fitted, 4);  // linear and waveform3 of rs-xx and wr-xx at least
}

TEST_F(StudyTest, StabilityMapAgreesWithADirectRunOfTheSameCell) {
  ASSERT_EQ(status_, 0) << output_;
  Scene scene = load_scene((dir_ / "short.toml").string());
  for (const auto& [method, H] :
       {std::pair{"wr-xt-jacobi", 5e-4}, std::pair{"rs-xx-jacobi", 5e-4}}) {
    const std::string json =
        read_file(dir_ / "out" / "sweep" / "H_0.0005" / method / "summary.json");
    run::RunOptions o;
    o.macro_step = H;
    o.tolerance = scene.tolerance;
    run::RunRecord direct =
        run::run_cosim(scene, parse_case(method), o, remote::inproc_factory(scene), "inproc");
    run::assess(direct, run::run_monolithic(scene, o), scene, parse_case(method), o);
    EXPECT_EQ(json_value(json, "status"), direct.status) << method;
  }
}

}  // namespace
}  // namespace railcosim
