// The FMU host's Fmu class (fmu/fmu) on the test FMUs of tests/fmus/:
// Dahlquist's equation stepped to its closed form bit for bit in FMI 2.0
// and 3.0, a state saved and restored repeating a step bit for bit, and the
// refusals: no state save, no binary for this platform, a failed step
// named with its function and time.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zip.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "fmu.hpp"
#include "fmu_error.hpp"

namespace fmu_host_test {
namespace fs = std::filesystem;
using namespace railcosim::fmu;

const std::string kFmus = std::string(RAILCOSIM_BIN_DIR) + "/fmus/";

// x(10) of the test FMU: 100 forward Euler steps of x' = -x from x = 1, as
// the FMU forms them (1 - 1 * 0.1 is 0.9 exactly in binary64).
double closed_form(int steps) {
  double x = 1;
  for (int i = 0; i < steps; ++i) x = 0.9 * x;
  return x;
}

void start(Fmu& f) {
  f.instantiate("test");
  f.setup(0, 10.0);
  f.enter_initialization();
  f.exit_initialization();
}

class FmuHost : public ::testing::TestWithParam<std::string> {};

TEST_P(FmuHost, StepsDahlquistToTheClosedFormBitForBit) {
  Fmu f(kFmus + GetParam() + ".fmu");
  start(f);
  EXPECT_EQ(f.get_real({0}), std::vector<double>{1.0});
  for (int n = 0; n < 100; ++n) f.do_step(n * 0.1, 0.1);
  const double x = f.get_real({0})[0];
  EXPECT_EQ(x, closed_form(100));  // bitwise
  EXPECT_NEAR(x, std::pow(0.9, 100), 1e-15 * x);
  EXPECT_DOUBLE_EQ(f.time(), 10.0);
  f.terminate();
}

TEST_P(FmuHost, SetsParametersAndInputsByValueReference) {
  Fmu f(kFmus + GetParam() + ".fmu");
  f.instantiate("test");
  f.setup(0);
  f.set_real({1}, {2.0});  // k = 2: x <- 0.8 x + 0.1 u
  f.enter_initialization();
  f.exit_initialization();
  f.set_real({2}, {5.0});
  f.do_step(0, 0.1);
  EXPECT_EQ(f.get_real({0, 1, 2}), (std::vector<double>{(1 - 2 * 0.1) * 1.0 + 0.1 * 5.0, 2, 5}));
  // A communication step of several internal steps.
  f.do_step(0.1, 0.3);
  double x = 0.8 + 0.5;
  for (int i = 0; i < 3; ++i) x = (1 - 2 * 0.1) * x + 0.1 * 5.0;
  EXPECT_EQ(f.get_real({0})[0], x);
}

TEST_P(FmuHost, RepeatsAStepFromASavedStateBitForBit) {
  Fmu f(kFmus + GetParam() + ".fmu");
  start(f);
  for (int n = 0; n < 50; ++n) f.do_step(n * 0.1, 0.1);
  const double saved_x = f.get_real({0})[0];
  FmuState s = f.get_state();
  f.do_step(5.0, 0.1);
  const double first = f.get_real({0})[0];
  f.do_step(5.1, 0.1);  // further on, so the restore has something to undo
  f.set_state(s);
  EXPECT_EQ(f.get_real({0})[0], saved_x);
  f.do_step(5.0, 0.1);
  EXPECT_EQ(f.get_real({0})[0], first);
  EXPECT_EQ(first, closed_form(51));
}

TEST_P(FmuHost, NamesTheFunctionAndTheTimeOfAFailedStep) {
  Fmu f(kFmus + GetParam() + ".fmu");
  start(f);
  for (int n = 0; n < 3; ++n) f.do_step(n * 0.1, 0.1);
  try {
    f.do_step(0.3, 0.15);  // not a multiple of the FMU's internal step
    FAIL() << "a step of 0.15 s was taken";
  } catch (const FmuError& e) {
    const std::string fn = GetParam() == "dahlquist3" ? "fmi3DoStep" : "fmi2DoStep";
    EXPECT_NE(std::string(e.what()).find("FMU " + GetParam() + ".fmu: " + fn +
                                         " at t = 0.3 s returned Error"),
              std::string::npos)
        << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(BothVersions, FmuHost, ::testing::Values("dahlquist2", "dahlquist3"));

TEST(FmuHostRefusals, AnFmuWithoutStateSaveSaysSo) {
  Fmu f(kFmus + "dahlquist2_nostate.fmu");
  start(f);
  f.do_step(0, 0.1);
  EXPECT_EQ(f.get_real({0})[0], 0.9);
  try {
    f.get_state();
    FAIL() << "a state was saved";
  } catch (const FmuError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "FMU dahlquist2_nostate.fmu cannot save its state (its description does not "
                  "say canGetAndSetFMUstate=\"true\")"),
              std::string::npos)
        << e.what();
  }
}

TEST(FmuHostRefusals, NamesThePlatformsPresentWhenThisOneIsMissing) {
  const fs::path dir = fs::temp_directory_path() / ("fmu-host-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "windows_only.fmu";
  std::ifstream in(std::string(RAILCOSIM_SOURCE_DIR) + "/tests/fmus/dahlquist2.xml");
  std::stringstream xml;
  xml << in.rdbuf();
  const std::string text = xml.str(), dll = "MZ";
  int error = 0;
  zip_t* z = zip_open(file.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  ASSERT_NE(z, nullptr);
  zip_file_add(z, "modelDescription.xml", zip_source_buffer(z, text.data(), text.size(), 0), 0);
  zip_file_add(z, "binaries/win64/dahlquist2.dll", zip_source_buffer(z, dll.data(), 2, 0), 0);
  zip_file_add(z, "binaries/darwin64/dahlquist2.dylib", zip_source_buffer(z, dll.data(), 2, 0), 0);
  ASSERT_EQ(zip_close(z), 0);
  try {
    Fmu f(file);
    FAIL() << "an FMU without a Linux binary was loaded";
  } catch (const FmuError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("windows_only.fmu: no binary for this platform "
                     "(binaries/linux64/dahlquist2.so); the FMU has binaries for: "),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("win64"), std::string::npos) << m;
    EXPECT_NE(m.find("darwin64"), std::string::npos) << m;
  }
  fs::remove_all(dir);
}

}  // namespace fmu_host_test
