// Progress of long work (`master run`, `master study`) on stderr, never on
// stdout, which scripts read: runs done of all, the macro step of each run
// under way, the time elapsed and an estimate of the time left.
//
// On a terminal it is one line, redrawn in place at most five times a
// second; otherwise a plain line every RAILCOSIM_PROGRESS_SECONDS seconds
// (default 30), each beginning "progress: ", so that a log keeps a trace of
// long work without filling up.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

namespace railcosim::run {

class Progress {
 public:
  // WHAT names the work ("study of scenes/paper.toml", a case name); RUNS
  // the runs it makes, SLOTS how many run at once. Draws on stderr when
  // `out` is null (a terminal if stderr is one).
  Progress(std::string what, long runs, int slots, std::FILE* out = nullptr);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress() { end(); }

  // The run in SLOT (its name) has done DONE of its TOTAL macro steps.
  void step(int slot, const std::string& run, long done, long total);
  // The run in SLOT has ended, whatever its outcome.
  void run_done(int slot);
  // Ends the line on a terminal (a newline); nothing more is drawn.
  void end();

  // The line as drawn now (also for tests).
  std::string line(double elapsed_s) const;

 private:
  struct Slot {
    std::string run;  // "" when idle
    long done = 0, total = 0;
  };
  void draw(bool force);

  mutable std::mutex mutex_;
  std::string what_;
  long runs_;
  long runs_done_ = 0;
  std::vector<Slot> slots_;
  std::FILE* out_;
  bool terminal_;
  double period_s_;
  bool drawn_ = false, ended_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

// "m:ss" or "h:mm:ss".
std::string clock_text(double seconds);

}  // namespace railcosim::run
