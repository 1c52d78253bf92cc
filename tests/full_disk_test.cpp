// The master on a full file system (a 64 KiB tmpfs): every write is
// checked, a failed run still leaves a summary saying why when anything can
// be written, there is no 0-byte file and no stray .part file. Needs the
// right to mount (CI runs as root); skipped otherwise.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "process_support.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using test::Outcome;
using test::read_file;
using test::run_master;

namespace fs = std::filesystem;

class FullDiskTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("railcosim_full_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    if (::mount("tmpfs", dir_.c_str(), "tmpfs", 0, "size=64k") != 0) {
      fs::remove_all(dir_);
      GTEST_SKIP() << "cannot mount a tmpfs here (needs root): " << std::strerror(errno);
    }
    mounted_ = true;
  }
  void TearDown() override {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // No 0-byte file and no .part file anywhere under the mount.
  void expect_no_empty_or_partial_files() {
    for (const auto& e : fs::recursive_directory_iterator(dir_)) {
      if (!e.is_regular_file()) continue;
      EXPECT_GT(e.file_size(), 0u) << e.path();
      EXPECT_NE(e.path().extension(), ".part") << e.path();
    }
  }

  fs::path dir_;
  bool mounted_ = false;
};

TEST_F(FullDiskTest, ARunFailsWithTheReasonAndLeavesItsSummary) {
  const Outcome o = run_master("run --scene " + test::source_path("scenes/paper.toml") +
                               " --case monolithic --out " + dir_.string());
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("history.csv: No space left on device"), std::string::npos) << o.output;
  const std::string summary = read_file(dir_ / "monolithic" / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"failed\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("No space left on device"), std::string::npos) << summary;
  expect_no_empty_or_partial_files();
}

// A disk so full that not even the run's folder can be made (no inode
// left): the message says where nothing could be written (before, it ended
// "history so far and summary in " and an empty path).
TEST_F(FullDiskTest, ARunWhoseFolderCannotBeMadeSaysSo) {
  ASSERT_EQ(::umount2(dir_.c_str(), MNT_DETACH), 0);
  ASSERT_EQ(::mount("tmpfs", dir_.c_str(), "tmpfs", 0, "size=64k,nr_inodes=1"), 0)
      << std::strerror(errno);
  const Outcome o = run_master("run --scene " + test::source_path("scenes/paper.toml") +
                               " --case monolithic --out " + dir_.string());
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("No space left on device"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("\n  no history or summary could be written under " +
                          (dir_ / "monolithic").string() + "\n"),
            std::string::npos)
      << o.output;
  EXPECT_EQ(o.output.find("summary in \n"), std::string::npos) << o.output;
}

TEST_F(FullDiskTest, AStudyNeverLeavesAnEmptyReport) {
  const Outcome o =
      run_master("study --scene " + test::source_path("scenes/paper.toml") + " --out " +
                 dir_.string() + " --transport inproc --macro-steps 1e-3 --tolerances 1e-5");
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("No space left on device"), std::string::npos) << o.output;
  // "report: ..." only for a report that is there, whole.
  if (o.output.find("report: ") != std::string::npos) {
    EXPECT_NE(read_file(dir_ / "REPORT.md").find("# Study of"), std::string::npos);
  }
  // Every summary that could be written says why its run failed.
  for (const auto& e : fs::recursive_directory_iterator(dir_))
    if (e.path().filename() == "summary.json") {
      const std::string s = read_file(e.path());
      if (s.find("\"status\": \"failed\"") != std::string::npos) {
        EXPECT_NE(s.find("No space left on device"), std::string::npos) << e.path() << s;
      }
    }
  expect_no_empty_or_partial_files();
}

}  // namespace
}  // namespace railcosim
