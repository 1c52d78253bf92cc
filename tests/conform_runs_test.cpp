// The conformance kit's whole runs: the reason a failed run is reported by
// (its error lines, never an informational log line), and the private
// folder they write into (mkdtemp: a new name, mode 0700, removed after).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli/conform_runs.hpp"

namespace railcosim::cli {
namespace {

const std::string kInfo =
    "[05:00:00.001] [master] [info] case ss-xx-jacobi: 200 macro steps on the relay plane\n"
    "[05:00:00.002] [master] [info] the soil participant at 127.0.0.1:4000: soil_node\n";

TEST(ConformRuns, TheReasonIsTheMastersErrorLineNotAnInfoLine) {
  const std::string log = kInfo +
                          "[05:00:01.000] [master] [error] the soil participant at "
                          "127.0.0.1:4000 failed macro step 12\n"
                          "master: run failed: the soil participant at 127.0.0.1:4000: "
                          "restore: state of another session\n";
  EXPECT_EQ(failure_reason(log, 1 << 8),
            "[05:00:01.000] [master] [error] the soil participant at 127.0.0.1:4000 failed "
            "macro step 12 | master: run failed: the soil participant at 127.0.0.1:4000: "
            "restore: state of another session");
}

TEST(ConformRuns, OnlyInfoLinesGiveTheExitStatus) {
  EXPECT_EQ(failure_reason(kInfo, 3 << 8), "exit status 3, and its output has no error line");
  EXPECT_EQ(failure_reason(kInfo + "Segmentation fault\n", SIGSEGV),
            "ended by signal 11, and its output has no error line; its last line: "
            "Segmentation fault");
}

TEST(ConformRuns, TheLastThreeErrorLinesAreQuoted) {
  std::string log = kInfo;
  for (int k = 1; k <= 5; ++k)
    log += "[05:00:01.000] [master] [warning] warning " + std::to_string(k) + "\n";
  EXPECT_EQ(failure_reason(log, 1 << 8),
            "[05:00:01.000] [master] [warning] warning 3 | [05:00:01.000] [master] [warning] "
            "warning 4 | [05:00:01.000] [master] [warning] warning 5");
}

TEST(ConformRuns, ThePrivateFolderIsNewOwnedAndRemoved) {
  const auto parent = std::filesystem::temp_directory_path();
  std::string first;
  {
    const PrivateFolder a(parent.string(), "railcosim-conform-test-");
    const PrivateFolder b(parent.string(), "railcosim-conform-test-");
    first = a.path();
    EXPECT_NE(a.path(), b.path());
    EXPECT_EQ(first.rfind((parent / "railcosim-conform-test-").string(), 0), 0u) << first;
    struct stat st {};
    ASSERT_EQ(::lstat(first.c_str(), &st), 0);
    EXPECT_TRUE(S_ISDIR(st.st_mode));
    EXPECT_EQ(st.st_mode & 07777, 0700u);
    EXPECT_EQ(st.st_uid, ::getuid());
    std::ofstream(std::filesystem::path(first) / "relay.log") << "x";
  }
  EXPECT_FALSE(std::filesystem::exists(first));
}

TEST(ConformRuns, AnUnwritableParentIsNamed) {
  try {
    const PrivateFolder f("/nonexistent-railcosim-parent", "railcosim-conform-");
    FAIL() << "made " << f.path();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot make a private temporary folder in "
                                         "/nonexistent-railcosim-parent"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace railcosim::cli
