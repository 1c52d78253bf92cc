// The study's answer with substep waveforms: a waveform run (in process
// only) can be the answer; in a TCP study it is compared only with runs in
// process, never rerun over TCP; the error-against-H slope is the
// least-squares fit of log(error) on log(H).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "study/report_front.hpp"
#include "study/report_methods.hpp"
#include "study/report_slopes.hpp"
#include "study/study_plan.hpp"

namespace railcosim {
namespace {

const char* kLinear = "rs-xx-jacobi+implicit-linear-iqn-ils";
const char* kCubic = "rs-xx-jacobi+implicit-waveform3-iqn-ils";

study::StudyRun study_run(const std::string& method, const std::string& transport, double H,
                          double wall, double error) {
  study::StudyRun r;
  r.group = "sweep";
  r.folder = transport + "/" + method + "/" + std::to_string(H);
  r.method = method;
  r.tolerance = 1e-7;
  r.record.case_name = "rs-xx-jacobi";
  r.record.status = "ok";
  r.record.transport = transport;
  r.record.macro_step = H;
  r.record.wall_s = wall;
  r.record.rel_l2_error = error;
  r.record.method = "implicit";
  r.record.accelerator = "iqn-ils";
  r.record.inputs = method == kCubic ? "waveform3" : "linear";
  r.rel_l2_error_converged = error;
  return r;
}

const study::FrontRow& row(const std::vector<study::FrontRow>& front, const std::string& cut,
                           const std::string& transport, double level) {
  for (const study::FrontRow& r : front)
    if (r.cut == cut && r.transport == transport && r.level == level) return r;
  throw std::runtime_error("no front row " + cut + " " + transport);
}

// In process, the cubic waveform reaching 1e-4 in half the time of the
// linear inputs is the answer at 1e-4; at 1e-3 the cheaper linear run is.
TEST(StudyFront, AWaveformRunIsTheAnswerWhereItIsCheapest) {
  const std::vector<study::StudyRun> runs{study_run(kLinear, "inproc", 5e-4, 0.5, 5e-4),
                                          study_run(kLinear, "inproc", 1e-4, 2.0, 5e-5),
                                          study_run(kCubic, "inproc", 5e-4, 1.0, 5e-5)};
  const auto front = study::study_front(runs, "inproc");
  EXPECT_EQ(row(front, "rs", "inproc", 1e-3).run, &runs[0]);
  EXPECT_EQ(row(front, "rs", "inproc", 1e-4).run, &runs[2]);
  EXPECT_EQ(row(front, "rs", "inproc", 1e-5).run, nullptr);
  std::ostringstream md;
  study::write_answer(md, front, "inproc");
  EXPECT_NE(md.str().find(std::string("`") + kCubic + "`, H = 0.0005 s"), std::string::npos)
      << md.str();
  EXPECT_EQ(md.str().find("in process\" hold"), std::string::npos) << md.str();
}

// A TCP study: the waveform run in process is faster than anything over TCP,
// yet the TCP column keeps its own cheapest; the waveform run is the answer
// of the cut's column "in process", and the headline names no in-process run.
TEST(StudyFront, InProcessRunsOfATcpStudyAreComparedOnlyWithEachOther) {
  const std::vector<study::StudyRun> runs{study_run(kLinear, "tcp", 1e-4, 3.0, 5e-5),
                                          study_run(kCubic, "inproc", 5e-4, 0.2, 5e-5)};
  const auto front = study::study_front(runs, "tcp");
  EXPECT_EQ(row(front, "rs", "tcp", 1e-4).run, &runs[0]);
  EXPECT_EQ(row(front, "rs", "inproc", 1e-4).run, &runs[1]);
  EXPECT_EQ(study::front_column(row(front, "rs", "inproc", 1e-4), "tcp"), "rs cut, in process");
  EXPECT_EQ(study::front_column(row(front, "rs", "tcp", 1e-4), "tcp"), "rs cut");
  std::ostringstream md;
  study::write_answer(md, front, "tcp");
  const std::string text = md.str();
  EXPECT_NE(text.find("| rs cut | rs cut, in process |"), std::string::npos) << text;
  const std::string headline = text.substr(text.find("The fastest of all"));
  EXPECT_EQ(headline.substr(0, headline.find('\n')).find(kCubic), std::string::npos) << text;
  EXPECT_NE(headline.substr(0, headline.find('\n')).find(kLinear), std::string::npos) << text;
}

// Stage 2 reruns the cheapest runs over the other transport: never a run
// that can travel in process only.
TEST(StudyFront, StageTwoNeverPlansAWaveformRunOverTcp) {
  study::StudyPlan stage1;
  stage1.transport = "tcp";
  std::vector<study::StudyRun> runs{study_run(kLinear, "tcp", 1e-4, 3.0, 5e-5),
                                    study_run(kCubic, "inproc", 5e-4, 0.2, 5e-6)};
  for (const study::StudyRun& r : runs) {
    study::PlannedRun p;
    p.folder = r.folder + "/rs-xx-jacobi";
    p.group = r.group;
    p.method = r.method;
    p.case_name = "rs-xx-jacobi";
    p.transport = r.record.transport;
    p.macro_step = r.record.macro_step;
    stage1.runs.push_back(p);
  }
  // The scene is one the product builds whole (a study of a soil it
  // starts, without a monolithic run, plans no stage 2 at all).
  study::PlannedRun whole;
  whole.case_name = "monolithic";
  whole.transport = "inproc";
  stage1.runs.push_back(whole);
  const study::StudyPlan second = study::other_transport_plan(stage1, runs);
  ASSERT_EQ(second.runs.size(), 1u);
  EXPECT_EQ(second.runs[0].method, kLinear);
  EXPECT_EQ(second.runs[0].transport, "inproc");
}

// error = 3 H^2.7 exactly: the fit gives 2.7; three points off one line:
// the closed form of least squares.
TEST(StudyFront, SlopeIsTheLeastSquaresFitOfLogErrorOnLogH) {
  std::vector<std::pair<double, double>> xy;
  for (double H : {1e-4, 2e-4, 5e-4, 1e-3}) xy.emplace_back(H, 3 * std::pow(H, 2.7));
  ASSERT_TRUE(study::log_log_slope(xy).has_value());
  EXPECT_NEAR(*study::log_log_slope(xy), 2.7, 1e-12);
  // x = 1, e, e^2 and log y = 0, 1, 3: slope sum((x-1)(y-4/3)) / sum((x-1)^2) = 3/2.
  const double e = std::exp(1.0);
  EXPECT_NEAR(*study::log_log_slope({{1, 1}, {e, e}, {e * e, e * e * e}}), 1.5, 1e-12);
  EXPECT_FALSE(study::log_log_slope({{1e-4, 1e-3}}).has_value());
  EXPECT_FALSE(study::log_log_slope({{1e-4, 1e-3}, {1e-4, 2e-3}}).has_value());

  std::vector<study::StudyRun> runs;
  for (double H : {1e-3, 1e-4, 5e-4}) {
    runs.push_back(study_run(kCubic, "inproc", H, 1, 2 * std::pow(H, 3.0)));
    runs.push_back(study_run(kLinear, "tcp", H, 1, 5 * std::pow(H, 2.0)));
  }
  runs.push_back(study_run("rs-xx-jacobi", "tcp", 1e-4, 1, 1e-3));  // explicit: not in the table
  runs.back().record.method = "explicit";
  const auto rows = study::error_slopes(runs);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].inputs, "linear");  // hold, linear, waveform0..3
  EXPECT_EQ(rows[1].inputs, "waveform3");
  EXPECT_NEAR(*rows[0].slope, 2.0, 1e-9);
  EXPECT_NEAR(*rows[1].slope, 3.0, 1e-9);
  EXPECT_EQ(rows[1].errors.front().first, 1e-4);  // ascending H
}

// A run judged against a co-simulation reference at its own macro step (the
// sweep's smallest H of a --node study) measures the reference's round-off:
// it is left out of the fit, and said so; the slope is the others' 2.
TEST(StudyFront, ARunJudgedAgainstAReferenceAtItsOwnStepIsNotFitted) {
  std::vector<study::StudyRun> runs;
  for (double H : {1e-4, 5e-4, 1e-3}) {
    runs.push_back(study_run(kLinear, "tcp", H, 1, H == 1e-4 ? 5.5e-11 : 5 * std::pow(H, 2.0)));
    runs.back().record.reference_kind = "co-simulation";
    runs.back().record.reference_macro_step = 1e-4;
  }
  const auto rows = study::error_slopes(runs);
  ASSERT_EQ(rows.size(), 1u);
  ASSERT_EQ(rows[0].errors.size(), 2u);
  EXPECT_NEAR(*rows[0].slope, 2.0, 1e-9);
  ASSERT_EQ(rows[0].left_out.size(), 1u);
  EXPECT_EQ(rows[0].left_out[0], 1e-4);
  std::ostringstream md;
  study::write_slopes_section(md, rows, "##", study::reference_words(runs));
  EXPECT_NE(md.str().find("against the co-simulation reference at each macro step H"),
            std::string::npos)
      << md.str();
  EXPECT_EQ(md.str().find("monolithic"), std::string::npos) << md.str();
  EXPECT_NE(md.str().find("left out H = 0.0001 s (judged against a co-simulation reference at "
                          "its own macro step)"),
            std::string::npos)
      << md.str();
}

// A study without a monolithic run (a participant given by address): the
// answer names the co-simulation reference and claims nothing of a
// monolithic run, and the front has no monolithic column.
TEST(StudyFront, AnAnswerWithoutAMonolithicRunNamesTheCosimReference) {
  std::vector<study::StudyRun> runs;
  for (double H : {1e-4, 5e-4}) {
    runs.push_back(study_run(kLinear, "tcp", H, H * 1e4, 2e-4 * H / 1e-4));
    runs.back().record.reference_kind = "co-simulation";
  }
  const auto front = study::study_front(runs, "tcp");
  std::ostringstream md;
  study::write_answer(md, front, "tcp");
  EXPECT_NE(md.str().find("(against the co-simulation reference)"), std::string::npos) << md.str();
  EXPECT_EQ(md.str().find("monolithic"), std::string::npos) << md.str();
  EXPECT_EQ(study::reference_words(runs), "the co-simulation reference");
  runs.back().record.reference_kind = "monolithic";
  runs.front().record.reference_kind = "monolithic";
  EXPECT_EQ(study::reference_words(runs), "the converged monolithic run");
}

}  // namespace
}  // namespace railcosim
