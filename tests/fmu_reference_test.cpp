// `master fmu check --reference REF.csv` (master/cli/fmu_reference) on the
// Dahlquist test FMUs of both versions: a record written here from the
// closed form (x = 0.9^n, steps = n, settled = 0.9^n < 1e-3 after n steps of
// 0.1 s) is reproduced exactly at every communication point, the rows
// between points and after the stop time are counted and not compared, an
// event's two rows at one time match either, a column the FMU lacks is
// named; one value off by 1e-3 fails at its time; bad files are refused
// naming the line. An FMU that carries its record (FMI layered standard for
// reference results) is held against it without --reference; FMUs that end
// the simulation at t = 5 s are compared up to there.
#include <gtest/gtest.h>
#include <zip.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "cli/fmu_check.hpp"
#include "fmu_error.hpp"
#include "process_support.hpp"

namespace fmu_reference_test {
using railcosim::cli::check_fmu;
using railcosim::cli::FmuCheckOptions;
using railcosim::cli::ReferenceComparison;
using railcosim::test::run_master;

const std::string kFmus = std::string(RAILCOSIM_BIN_DIR) + "/fmus/";

std::string row(double t, double x, int n, bool settled) {
  char line[160];
  std::snprintf(line, sizeof line, "%.17g,%.17g,%d,%s,0\n", t, x, n, settled ? "true" : "false");
  return line;
}

// The closed form at t = 0, 0.1, ..., 10; `off` multiplies x at step 5.
std::string closed_form_csv(double off = 1) {
  std::string csv = "\"time\",\"x\",\"steps\",\"settled\",\"y\"\n";
  double x = 1;
  for (int n = 0; n <= 100; ++n) {
    const double t = n * 0.1;
    if (n == 1) csv += row(0.05, 1, 0, false);  // between two points: counted, not compared
    if (n == 66) csv += row(t, x, n, false);    // an event's row before: the FMU matches the after
    csv += row(t, n == 5 ? x * off : x, n, x < 1e-3);
    x = 0.9 * x;
  }
  csv += row(10.1, x, 101, true);  // after the stop time
  return csv;
}

std::string write(const std::string& name, const std::string& text) {
  const auto dir = railcosim::test::temp_dir("fmu_reference");
  const std::string file = (dir / name).string();
  std::ofstream(file) << text;
  return file;
}

class FmuReference : public ::testing::TestWithParam<std::string> {};

TEST_P(FmuReference, TheClosedFormIsReproducedAtEveryCommunicationPoint) {
  FmuCheckOptions o;
  o.reference = write("dahlquist_ref.csv", closed_form_csv());
  const auto r = check_fmu(kFmus + GetParam() + ".fmu", o);
  ASSERT_TRUE(r.reference.has_value()) << r.run_error;
  const ReferenceComparison& c = *r.reference;
  EXPECT_EQ(c.rows, 104);
  EXPECT_EQ(c.on_grid, 102);  // 101 points, one of them twice
  EXPECT_EQ(c.between, 1);
  EXPECT_EQ(c.after_stop, 1);
  ASSERT_EQ(c.columns.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(c.columns[i].skipped, "") << c.columns[i].name;
    EXPECT_EQ(c.columns[i].compared, 101) << c.columns[i].name;
    EXPECT_EQ(c.columns[i].worst, 0.0) << c.columns[i].name;  // the same products, bit for bit
    EXPECT_TRUE(c.columns[i].pass) << c.columns[i].name;
  }
  EXPECT_EQ(c.columns[1].scale, 100.0);
  EXPECT_EQ(c.columns[3].skipped, "the FMU has no variable of that name");
  EXPECT_TRUE(c.pass());
  // Every output at the end, the discrete ones too.
  ASSERT_EQ(r.final_outputs.size(), 3u);
  EXPECT_EQ(r.final_outputs[1], std::make_pair(std::string("steps"), 100.0));
  EXPECT_EQ(r.final_outputs[2], std::make_pair(std::string("settled"), 1.0));
}

TEST_P(FmuReference, AValueOffByAThousandthFailsAtItsTime) {
  FmuCheckOptions o;
  o.reference = write("dahlquist_off.csv", closed_form_csv(1 + 1e-3));
  const auto r = check_fmu(kFmus + GetParam() + ".fmu", o);
  ASSERT_TRUE(r.reference.has_value()) << r.run_error;
  const auto& x = r.reference->columns[0];
  EXPECT_FALSE(x.pass);
  EXPECT_EQ(x.worst_t, 0.5);
  EXPECT_NEAR(x.worst, 1e-3 * std::pow(0.9, 5), 1e-15);
  EXPECT_FALSE(r.reference->pass());
  const auto out =
      run_master("fmu check " + kFmus + GetParam() + ".fmu --reference " + o.reference);
  EXPECT_EQ(out.status, 1) << out.output;
  EXPECT_NE(out.output.find("reference: FAIL (3 of 4 columns compared)"), std::string::npos)
      << out.output;
  EXPECT_NE(out.output.find("at t = 0.5 s"), std::string::npos) << out.output;
}

INSTANTIATE_TEST_SUITE_P(BothVersions, FmuReference, ::testing::Values("dahlquist2", "dahlquist3"));

TEST(FmuReferenceCli, APassingReferenceExitsZeroAndSaysWhatItCompared) {
  const std::string ref = write("dahlquist_ref.csv", closed_form_csv());
  const auto out = run_master("fmu check " + kFmus + "dahlquist2_nostate.fmu --reference " + ref);
  EXPECT_EQ(out.status, 0) << out.output;
  EXPECT_NE(out.output.find(": 104 rows, 102 at communication points, 1 between them and 1 after "
                            "the stop time (not compared)"),
            std::string::npos)
      << out.output;
  EXPECT_NE(out.output.find("  y                        not compared: the FMU has no variable "
                            "of that name"),
            std::string::npos)
      << out.output;
  EXPECT_NE(out.output.find("reference: PASS (3 of 4 columns compared)"), std::string::npos)
      << out.output;
}

TEST(FmuReferenceCli, BadFilesAreRefusedNamingTheLine) {
  const std::string fmu = kFmus + "dahlquist3.fmu";
  auto refused = [&](const std::string& text) {
    const auto out = run_master("fmu check " + fmu + " --reference " + write("bad.csv", text));
    EXPECT_EQ(out.status, 2) << out.output;
    return out.output;
  };
  EXPECT_NE(refused("t,x\n0,1\n").find("bad.csv:1: the header's first column is not \"time\""),
            std::string::npos);
  EXPECT_NE(refused("time,x\n0,1\n0.1,0.9,3\n")
                .find("bad.csv:3: a row of 3 cells under a header "
                      "of 2"),
            std::string::npos);
  EXPECT_NE(refused("time,x\n0.2,1\n0.1,0.9\n").find("bad.csv:3: the time goes back"),
            std::string::npos);
  EXPECT_NE(refused("time,x\n").find("bad.csv: no rows under the header"), std::string::npos);
}

// dahlquist3.fmu again with `extra` entries added.
std::string with_extra(const std::string& name,
                       const std::vector<std::pair<std::string, std::string>>& extra) {
  const std::string out = (railcosim::test::temp_dir("fmu_reference_zip") / name).string();
  int error = 0;
  zip_t* in = zip_open((kFmus + "dahlquist3.fmu").c_str(), ZIP_RDONLY, &error);
  zip_t* z = zip_open(out.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  std::vector<std::string> keep;  // the buffers live until zip_close
  keep.reserve(64);
  for (zip_int64_t i = 0; i < zip_get_num_entries(in, 0); ++i) {
    zip_stat_t st;
    zip_stat_index(in, static_cast<zip_uint64_t>(i), 0, &st);
    std::string data(st.size, '\0');
    zip_file_t* f = zip_fopen_index(in, static_cast<zip_uint64_t>(i), 0);
    zip_fread(f, data.data(), st.size);
    zip_fclose(f);
    keep.push_back(std::move(data));
    zip_file_add(z, st.name, zip_source_buffer(z, keep.back().data(), keep.back().size(), 0), 0);
  }
  for (const auto& [entry, text] : extra)
    zip_file_add(z, entry.c_str(), zip_source_buffer(z, text.data(), text.size(), 0), 0);
  zip_close(z);
  zip_close(in);
  return out;
}

std::string manifest(const std::string& source) {
  return "<fmiReferences><Related type=\"text/csv\" source=\"" + source +
         "\" role=\"result\"/></fmiReferences>";
}

TEST(FmuReferenceEmbedded, AnFmuCarryingItsRecordIsHeldAgainstIt) {
  const std::string dir = "extra/org.fmi-standard.fmi-ls-ref/";
  const std::string fmu =
      with_extra("carries.fmu", {{dir + "fmi-ls-manifest.xml", manifest("d_out.csv")},
                                 {dir + "d_out.csv", closed_form_csv()}});
  const auto r = check_fmu(fmu);
  ASSERT_TRUE(r.reference.has_value()) << r.run_error;
  EXPECT_EQ(r.reference->file, dir + "d_out.csv (the FMU's own)");
  EXPECT_TRUE(r.reference->pass());
  EXPECT_EQ(r.reference->columns[0].compared, 101);
  // A record off by a thousandth at t = 0.5 s fails the check.
  const std::string off =
      with_extra("carries_off.fmu", {{dir + "fmi-ls-manifest.xml", manifest("d_out.csv")},
                                     {dir + "d_out.csv", closed_form_csv(1 + 1e-3)}});
  const auto out = run_master("fmu check " + off);
  EXPECT_EQ(out.status, 1) << out.output;
  EXPECT_NE(out.output.find("reference extra/org.fmi-standard.fmi-ls-ref/d_out.csv (the FMU's "
                            "own): 104 rows"),
            std::string::npos)
      << out.output;
  // A manifest whose source climbs out of its folder is refused.
  const std::string climbs =
      with_extra("climbs.fmu", {{dir + "fmi-ls-manifest.xml", manifest("../x.csv")}});
  const auto refused = run_master("fmu check " + climbs);
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("the result's source '../x.csv' is not a file name in that folder"),
            std::string::npos)
      << refused.output;
  // Without a record, no reference section.
  EXPECT_FALSE(check_fmu(kFmus + "dahlquist3.fmu").reference.has_value());
}

class FmuStops : public ::testing::TestWithParam<std::string> {};

TEST_P(FmuStops, AnFmuThatEndsTheSimulationIsComparedUpToWhereItEnded) {
  FmuCheckOptions o;
  o.reference = write("dahlquist_ref.csv", closed_form_csv());
  const auto r = check_fmu(kFmus + GetParam() + ".fmu", o);
  EXPECT_TRUE(r.ran) << r.run_error;
  ASSERT_TRUE(r.ended_at.has_value());
  EXPECT_NEAR(*r.ended_at, 5.0, 1e-12);
  EXPECT_EQ(r.final_outputs.at(1).second, 50.0);  // steps: 50 of the 100
  ASSERT_TRUE(r.reference.has_value());
  EXPECT_EQ(r.reference->columns[0].compared, 51);  // t = 0 to 5 s
  EXPECT_EQ(r.reference->columns[0].worst, 0.0);
  EXPECT_TRUE(r.reference->pass());
  const auto out = run_master("fmu check " + kFmus + GetParam() + ".fmu");
  EXPECT_EQ(out.status, 0) << out.output;
  EXPECT_NE(out.output.find(": PASS (the FMU ended the simulation at t = 5 s)"), std::string::npos)
      << out.output;
  EXPECT_NE(out.output.find("  steps = 50 at t = 5 s"), std::string::npos) << out.output;
}

INSTANTIATE_TEST_SUITE_P(BothVersions, FmuStops,
                         ::testing::Values("dahlquist2_stops", "dahlquist3_stops"));

}  // namespace fmu_reference_test
