// `master fmu check` (master/cli/fmu_check) on the test FMUs of
// tests/fmus/: the default experiment's final x equal to 0.9^100 bit for
// bit, the state round trip passed, failed on an FMU whose restore forgets
// its state, and not offered by the FMU without state save, which is
// reported as explicit only; hostile archives refused with messages.
#include <gtest/gtest.h>
#include <zip.h>

#include <string>

#include "cli/fmu_check.hpp"
#include "fmu_error.hpp"
#include "process_support.hpp"

namespace fmu_check_test {
using railcosim::cli::check_fmu;
using railcosim::cli::FmuCheckReport;
using railcosim::test::run_master;

const std::string kFmus = std::string(RAILCOSIM_BIN_DIR) + "/fmus/";

double closed_form(int steps = 100) {
  double x = 1;
  for (int i = 0; i < steps; ++i) x = 0.9 * x;
  return x;
}

std::string verdict_of(const FmuCheckReport& r, const std::string& coupling) {
  for (const auto& [c, v] : r.couplings)
    if (c.rfind(coupling, 0) == 0) return v;
  return "(no such coupling)";
}

class FmuCheck : public ::testing::TestWithParam<std::string> {};

TEST_P(FmuCheck, RunsTheDefaultExperimentToTheClosedFormAndRepeatsAStep) {
  const FmuCheckReport r = check_fmu(kFmus + GetParam() + ".fmu");
  EXPECT_TRUE(r.ran) << r.run_error;
  EXPECT_EQ(r.steps, 100);
  EXPECT_EQ(r.step, 0.1);
  ASSERT_EQ(r.final_outputs.size(), 3u);  // x, steps (100), settled (1)
  EXPECT_EQ(r.final_outputs[0].first, "x");
  EXPECT_EQ(r.final_outputs[1].second, 100.0);
  EXPECT_EQ(r.final_outputs[2].second, 1.0);
  EXPECT_EQ(r.final_outputs[0].second, closed_form());  // bit for bit: the same products
  EXPECT_EQ(r.round_trip, FmuCheckReport::RoundTrip::kPass) << r.round_trip_detail;
  EXPECT_FALSE(r.explicit_only);
  EXPECT_EQ(verdict_of(r, "implicit"), "yes");
  EXPECT_EQ(verdict_of(r, "judged"), "yes");
  EXPECT_EQ(verdict_of(r, "explicit, held"), "yes");
}

INSTANTIATE_TEST_SUITE_P(BothVersions, FmuCheck, ::testing::Values("dahlquist2", "dahlquist3"));

TEST(FmuCheckVerdicts, AnFmuWithoutStateSaveIsExplicitOnlyAndNotJudged) {
  const FmuCheckReport r = check_fmu(kFmus + "dahlquist2_nostate.fmu");
  EXPECT_TRUE(r.ran) << r.run_error;
  EXPECT_EQ(r.final_outputs.at(0).second, closed_form());
  EXPECT_EQ(r.round_trip, FmuCheckReport::RoundTrip::kNotOffered);
  EXPECT_TRUE(r.explicit_only);
  EXPECT_EQ(verdict_of(r, "implicit"), "no: the FMU cannot save its state");
  EXPECT_EQ(verdict_of(r, "judged"), "not judged: the FMU cannot save its state");
  EXPECT_EQ(verdict_of(r, "explicit, held"), "yes");
  const auto o = run_master("fmu check " + kFmus + "dahlquist2_nostate.fmu");
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("state round trip: SKIP: the FMU cannot save its state"),
            std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("verdict: explicit coupling only"), std::string::npos) << o.output;
}

TEST(FmuCheckVerdicts, ARestoreThatForgetsTheStateFailsTheRoundTrip) {
  const FmuCheckReport r = check_fmu(kFmus + "dahlquist3_badstate.fmu");
  EXPECT_EQ(r.round_trip, FmuCheckReport::RoundTrip::kFail);
  EXPECT_EQ(r.round_trip_detail,
            "after the restore before the step from t = 5 s the variables differ from those "
            "saved");
  EXPECT_TRUE(r.explicit_only);
  EXPECT_EQ(verdict_of(r, "implicit"), "no: its state round trip failed");
  const auto o = run_master("fmu check " + kFmus + "dahlquist3_badstate.fmu");
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("state round trip: FAIL"), std::string::npos) << o.output;
  // The step taken again on the x its restore kept: one Euler step more.
  char x[64];
  std::snprintf(x, sizeof x, "  x = %.17g at t = 10 s", closed_form(101));
  EXPECT_NE(o.output.find(x), std::string::npos) << o.output;
}

TEST(FmuCheckVerdicts, PrintsTheFinalValueAndExitsZeroOnAGoodFmu) {
  const auto o = run_master("fmu check " + kFmus + "dahlquist3.fmu");
  EXPECT_EQ(o.status, 0) << o.output;
  char x[64];
  std::snprintf(x, sizeof x, "  x = %.17g at t = 10 s", closed_form());
  EXPECT_NE(o.output.find(x), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("FMI 3.0 co-simulation"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("state round trip: PASS"), std::string::npos) << o.output;
}

// `master fmu check` on an archive of `entries` (name, content; a link when
// `link` names one of them): its exit status and output.
railcosim::test::Outcome check_archive(
    const std::vector<std::pair<std::string, std::string>>& entries, const std::string& link = "") {
  const auto dir = railcosim::test::temp_dir("fmu_check");
  const std::string file = (dir / "hostile.fmu").string();
  int error = 0;
  zip_t* z = zip_open(file.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  for (const auto& [name, content] : entries) {
    const zip_int64_t at =
        zip_file_add(z, name.c_str(), zip_source_buffer(z, content.data(), content.size(), 0), 0);
    if (name == link)
      zip_file_set_external_attributes(z, static_cast<zip_uint64_t>(at), 0, ZIP_OPSYS_UNIX,
                                       static_cast<zip_uint32_t>(0120777) << 16);
  }
  zip_close(z);
  auto o = run_master("fmu check " + file);
  std::filesystem::remove_all(dir);
  return o;
}

TEST(FmuCheckRefusals, HostileArchivesAreRefusedWithAMessage) {
  const std::string md =
      railcosim::test::read_file(std::string(RAILCOSIM_SOURCE_DIR) + "/tests/fmus/dahlquist2.xml");
  auto o = check_archive({{"modelDescription.xml", md}, {"../../escaped.so", "x"}});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("master fmu check: refused: "), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("entry '../../escaped.so' climbs out of the folder"), std::string::npos)
      << o.output;
  o = check_archive({{"modelDescription.xml", md}, {"binaries/linux64/dahlquist2.so", "/bin/sh"}},
                    "binaries/linux64/dahlquist2.so");
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("entry 'binaries/linux64/dahlquist2.so' is a symbolic link"),
            std::string::npos)
      << o.output;
  o = check_archive({{"modelDescription.xml",
                      R"(<fmiModelDescription fmiVersion="2.0" guid="g">
                         <ModelExchange modelIdentifier="m"/></fmiModelDescription>)"}});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("the FMU offers model exchange only"), std::string::npos) << o.output;
  o = check_archive({{"modelDescription.xml", md}, {"binaries/win64/dahlquist2.dll", "MZ"}});
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("no binary for this platform (binaries/linux64/dahlquist2.so); the FMU "
                          "has binaries for: win64"),
            std::string::npos)
      << o.output;
}

}  // namespace fmu_check_test
