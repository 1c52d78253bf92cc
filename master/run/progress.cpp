#include "run/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace railcosim::run {
namespace {

constexpr double kTerminalPeriod = 0.2;
constexpr double kPlainPeriod = 30.0;

// RAILCOSIM_PROGRESS_SECONDS, when a positive number, else the default.
double plain_period() {
  const char* text = std::getenv("RAILCOSIM_PROGRESS_SECONDS");
  if (text == nullptr) return kPlainPeriod;
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(v) && v > 0 ? v : kPlainPeriod;
}

}  // namespace

std::string clock_text(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

Progress::Progress(std::string what, long runs, int slots, std::FILE* out)
    : what_(std::move(what)),
      runs_(runs),
      slots_(static_cast<std::size_t>(std::max(1, slots))),
      out_(out != nullptr ? out : stderr),
      terminal_(out == nullptr && ::isatty(STDERR_FILENO) != 0),
      period_s_(terminal_ ? kTerminalPeriod : plain_period()),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

std::string Progress::line(double elapsed_s) const {
  std::ostringstream s;
  s << what_ << ": " << runs_done_ << "/" << runs_ << (runs_ == 1 ? " run" : " runs") << " done";
  double fraction = static_cast<double>(runs_done_);
  for (const Slot& x : slots_) {
    if (x.run.empty() || x.total <= 0) continue;
    s << "; " << x.run << " step " << x.done << "/" << x.total;
    fraction += static_cast<double>(x.done) / static_cast<double>(x.total);
  }
  fraction /= static_cast<double>(std::max(1L, runs_));
  s << "; elapsed " << clock_text(elapsed_s);
  if (fraction >= 0.01 && fraction < 1.0)
    s << ", about " << clock_text(elapsed_s * (1.0 - fraction) / fraction) << " left";
  else if (fraction < 1.0)
    s << ", time left not yet known";
  return s.str();
}

void Progress::draw(bool force) {
  if (ended_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && std::chrono::duration<double>(now - last_).count() < period_s_) return;
  last_ = now;
  const std::string text = line(std::chrono::duration<double>(now - start_).count());
  if (terminal_) {
    // Back to the line's start and clear it: the line may have shortened.
    std::fprintf(out_, "\r%s\033[K", text.c_str());
    drawn_ = true;
  } else {
    std::fprintf(out_, "progress: %s\n", text.c_str());
  }
  std::fflush(out_);
}

void Progress::step(int slot, const std::string& run, long done, long total) {
  std::lock_guard lock(mutex_);
  Slot& x = slots_[static_cast<std::size_t>(slot) % slots_.size()];
  x.run = run;
  x.done = done;
  x.total = total;
  draw(false);
}

void Progress::run_done(int slot) {
  std::lock_guard lock(mutex_);
  slots_[static_cast<std::size_t>(slot) % slots_.size()] = Slot{};
  ++runs_done_;
  draw(terminal_);  // a terminal shows every run done at once
}

void Progress::end() {
  std::lock_guard lock(mutex_);
  if (ended_) return;
  if (terminal_ && drawn_) {
    draw(true);
    std::fputs("\n", out_);
    std::fflush(out_);
  }
  ended_ = true;
}

}  // namespace railcosim::run
