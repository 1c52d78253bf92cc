// history.csv in blocks: lines reach the file a block at a time (by count or
// by age), everything on close, and every path out of a failed run flushes.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "process_support.hpp"
#include "run/block_writer.hpp"
#include "run/run_output.hpp"

namespace railcosim {
namespace {

using run::BlockWriter;
using run::RunRecord;
using run::RunWriter;

namespace fs = std::filesystem;
using namespace std::chrono_literals;

using test::temp_dir;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

long lines(const fs::path& p) {
  const std::string t = read(p);
  return std::count(t.begin(), t.end(), '\n');
}

// A clock the test moves by hand.
struct FakeClock {
  BlockWriter::Clock::time_point t{};
  std::function<BlockWriter::Clock::time_point()> fn() {
    return [this] { return t; };
  }
};

TEST(BlockWriter, WritesABlockOnceItHoldsTheRowLimit) {
  const fs::path dir = temp_dir("block_rows");
  FakeClock clock;  // never moves: only the row count decides
  BlockWriter w(dir / "h.csv", {3, 1h}, clock.fn());
  w.append("a\n");
  w.append("b\n");
  EXPECT_EQ(lines(dir / "h.csv"), 0);
  EXPECT_EQ(w.lines_held(), 2);
  w.append("c\n");
  EXPECT_EQ(read(dir / "h.csv"), "a\nb\nc\n");
  EXPECT_EQ(w.lines_written(), 3);
  w.append("d\n");
  EXPECT_EQ(lines(dir / "h.csv"), 3);
  w.close();  // everything on close
  EXPECT_EQ(read(dir / "h.csv"), "a\nb\nc\nd\n");
  EXPECT_EQ(w.lines_written(), 4);
  EXPECT_EQ(w.lines_held(), 0);
  fs::remove_all(dir);
}

TEST(BlockWriter, WritesABlockWhoseFirstRowHasWaitedTheAgeLimit) {
  const fs::path dir = temp_dir("block_age");
  FakeClock clock;
  BlockWriter w(dir / "h.csv", {1000, 100ms}, clock.fn());
  w.append("a\n");
  clock.t += 99ms;
  w.append("b\n");
  EXPECT_EQ(lines(dir / "h.csv"), 0) << "the first row has waited 99 ms of 100";
  clock.t += 1ms;
  w.append("c\n");
  EXPECT_EQ(read(dir / "h.csv"), "a\nb\nc\n");
  // The next block's age counts from its own first row.
  clock.t += 50ms;
  w.append("d\n");
  clock.t += 99ms;
  w.append("e\n");
  EXPECT_EQ(lines(dir / "h.csv"), 3);
  clock.t += 1ms;
  w.append("f\n");
  EXPECT_EQ(lines(dir / "h.csv"), 6);
  fs::remove_all(dir);
}

TEST(BlockWriter, AnExceptionUnwindingTheWriterFlushesIt) {
  const fs::path dir = temp_dir("block_unwind");
  try {
    BlockWriter w(dir / "h.csv", {1000, 1h});
    w.append("a\n");
    w.append("b\n");
    throw std::runtime_error("the run failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(read(dir / "h.csv"), "a\nb\n");
  fs::remove_all(dir);
}

// A file size limit (RLIMIT_FSIZE) makes a write stop short, then fail with
// EFBIG: the file keeps its whole lines only, and the error names the file.
TEST(BlockWriter, AFailedWriteLeavesWholeLinesAndNamesTheFile) {
  const fs::path dir = temp_dir("block_fail");
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  BlockWriter w(dir / "h.csv", {4, 1h});
  rlimit small = old;
  small.rlim_cur = 10;  // bytes: "row1\nrow2\n" fits, the third row is cut
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string error;
  try {
    for (const char* row : {"row1\n", "row2\n", "row3\n", "row4\n"}) w.append(row);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(error.find("cannot write " + (dir / "h.csv").string() + ": File too large"),
            std::string::npos)
      << error;
  EXPECT_EQ(read(dir / "h.csv"), "row1\nrow2\n");
  EXPECT_EQ(w.lines_written(), 2);
  w.append("row5\n");  // a failed writer writes nothing more
  w.close();
  EXPECT_EQ(read(dir / "h.csv"), "row1\nrow2\n");
  fs::remove_all(dir);
}

HistoryRow row_at(double t) {
  return {t, 1e-3 * t, 1e5 + t, {}};
}

TEST(RunWriter, AFailedRunKeepsEveryRowAndTheSummaryCountsThem) {
  const fs::path out = temp_dir("runwriter_failed");
  RunWriter writer(out, "case");
  writer.channels({});
  for (int n = 0; n < 7; ++n) writer.row(row_at(n * 1e-4));
  // Seven rows are far below a block: none has reached the file yet.
  EXPECT_EQ(writer.history_rows(), 0);
  RunRecord failed;
  failed.case_name = "case";
  failed.status = "failed";
  failed.message = "track node at 127.0.0.1:1: the peer closed the connection at macro step 6";
  writer.finish(failed);
  EXPECT_EQ(lines(out / "case" / "history.csv"), 8);  // the header and seven rows
  const std::string summary = read(out / "case" / "summary.json");
  EXPECT_NE(summary.find("\"history_rows\": 7,"), std::string::npos) << summary;
  EXPECT_NE(summary.find("at macro step 6"), std::string::npos) << summary;
  fs::remove_all(out);
}

TEST(RunWriter, AWriterDestroyedWithoutFinishingKeepsItsRows) {
  const fs::path out = temp_dir("runwriter_unwind");
  {
    RunWriter writer(out, "case");
    writer.channels({});
    for (int n = 0; n < 5; ++n) writer.row(row_at(n * 1e-4));
  }
  const std::string h = read(out / "case" / "history.csv");
  EXPECT_EQ(h.rfind("t_s,wheel_m,contact_force_N\n", 0), 0u) << h;
  EXPECT_EQ(std::count(h.begin(), h.end(), '\n'), 6);
  fs::remove_all(out);
}

}  // namespace
}  // namespace railcosim
