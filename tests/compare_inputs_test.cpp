// `master compare` on a folder someone sent: a history.csv that is a FIFO
// (it once waited forever), a link to /dev/zero (80 s and 2 GiB), a file over
// the size bound, a header of too many columns; and the memory a large file
// of one-character cells takes (it once took some 29 bytes per byte read).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "cli/compare.hpp"
#include "process_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A run folder holding `history` as its history.csv.
fs::path run_folder(const fs::path& at, const std::string& history) {
  fs::create_directories(at);
  std::ofstream(at / "history.csv") << history;
  return at;
}

struct Compared {
  test::Outcome outcome;
  double seconds = 0;
};

Compared compare(const fs::path& a, const fs::path& b, const std::string& flags = "") {
  const auto t0 = Clock::now();
  Compared c;
  c.outcome = test::run_master("compare " + a.string() + " " + b.string() + " " + flags);
  c.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return c;
}

class CompareInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("compare_inputs");
    reference_ = run_folder(dir_ / "reference", "t,u\n0,1\n0.1,2\n");
    fs::create_directories(dir_ / "other");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path other_history() const { return dir_ / "other" / "history.csv"; }
  fs::path dir_, reference_;
};

TEST_F(CompareInputs, AgreeingAndDifferingFoldersAreStillJudged) {
  run_folder(dir_ / "other", "t,u\n0,1\n0.1,2\n");
  EXPECT_EQ(compare(reference_, dir_ / "other").outcome.status, 0);
  std::ofstream(other_history()) << "t,u\n0,1\n0.1,2.5\n";
  const Compared c = compare(reference_, dir_ / "other");
  EXPECT_EQ(c.outcome.status, 1) << c.outcome.output;
  EXPECT_NE(c.outcome.output.find("differ: history.csv: column u by 0.25 relative"),
            std::string::npos)
      << c.outcome.output;
  std::ofstream(other_history()) << "t,u\n0,1\n";
  EXPECT_NE(compare(reference_, dir_ / "other").outcome.output.find("2 rows, the other 1"),
            std::string::npos);
  std::ofstream(other_history()) << "t,u\n0,1\n0.1,x\n";
  const Compared bad = compare(reference_, dir_ / "other");
  EXPECT_EQ(bad.outcome.status, 2);
  EXPECT_NE(bad.outcome.output.find("history.csv:3: column u: 'x' is not a number"),
            std::string::npos)
      << bad.outcome.output;
}

TEST_F(CompareInputs, AFifoIsRefusedAtOnceNamingTheFile) {
  ASSERT_EQ(::mkfifo(other_history().c_str(), 0600), 0);
  const Compared c = compare(reference_, dir_ / "other");
  EXPECT_EQ(c.outcome.status, 2) << c.outcome.output;
  EXPECT_LT(c.seconds, 5.0);
  EXPECT_NE(c.outcome.output.find(other_history().string() + ": not a regular file"),
            std::string::npos)
      << c.outcome.output;
}

TEST_F(CompareInputs, ALinkToADeviceIsRefused) {
  fs::create_symlink("/dev/zero", other_history());
  const Compared c = compare(reference_, dir_ / "other");
  EXPECT_EQ(c.outcome.status, 2) << c.outcome.output;
  EXPECT_LT(c.seconds, 5.0);
  EXPECT_NE(c.outcome.output.find(other_history().string() + ": not a regular file"),
            std::string::npos)
      << c.outcome.output;
}

TEST_F(CompareInputs, AFileOverTheBoundIsRefusedWithTheBoundNamed) {
  {
    std::ofstream out(other_history());
    out << "t,u\n";
    for (int k = 0; k < 200000; ++k) out << k << ",1\n";  // some 1.5 MB
  }
  const Compared c = compare(reference_, dir_ / "other", "--max-file-mb 1");
  EXPECT_EQ(c.outcome.status, 2) << c.outcome.output;
  EXPECT_NE(c.outcome.output.find(other_history().string() + ": " +
                                  std::to_string(fs::file_size(other_history())) +
                                  " bytes, over the bound of 1048576 bytes (--max-file-mb)"),
            std::string::npos)
      << c.outcome.output;
}

TEST_F(CompareInputs, AHeaderOfTooManyColumnsOrALineTooLongIsRefused) {
  std::string header(2 * cli::kMaxCsvColumns, ',');
  std::ofstream(other_history()) << header << "\n";
  Compared c = compare(reference_, dir_ / "other");
  EXPECT_EQ(c.outcome.status, 2) << c.outcome.output;
  EXPECT_NE(c.outcome.output.find(other_history().string() + ":1: over 65536 columns: refused"),
            std::string::npos)
      << c.outcome.output;
  std::ofstream(other_history()) << std::string(cli::kMaxCsvLineBytes + 1, 'x') << "\n";
  c = compare(reference_, dir_ / "other");
  EXPECT_EQ(c.outcome.status, 2) << c.outcome.output;
  EXPECT_NE(c.outcome.output.find(other_history().string() + ":1: a line over 4194304 bytes"),
            std::string::npos)
      << c.outcome.output;
}

// The peak resident memory of this process, KiB.
long peak_kib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

// 2 x 24 MB of one-character cells compared: the memory stays a few numbers
// per column, not the cells.
TEST_F(CompareInputs, MemoryDoesNotGrowWithTheRows) {
  const std::string header = [] {
    std::string h = "c0";
    for (int k = 1; k < 64; ++k) h += ",c" + std::to_string(k);
    return h;
  }();
  std::string row = "1";
  for (int k = 1; k < 64; ++k) row += ",1";
  for (const fs::path& d : {reference_, dir_ / "other"}) {
    std::ofstream out(d / "history.csv");
    out << header << "\n";
    for (int k = 0; k < 190000; ++k) out << row << "\n";
  }
  const long before = peak_kib();
  const cli::RunComparison r = cli::compare_runs(reference_, dir_ / "other", 0, 1u << 30);
  EXPECT_TRUE(r.agree());
  EXPECT_LT(peak_kib() - before, 8 * 1024) << "KiB";
}

}  // namespace
}  // namespace railcosim
