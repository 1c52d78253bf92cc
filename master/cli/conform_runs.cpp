#include "cli/conform_runs.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

namespace railcosim::cli {
namespace {

using Clock = std::chrono::steady_clock;

// A run's log is read up to this size (its end: the error lines come last).
constexpr std::uintmax_t kLogLimit = 1 << 20;
// The error lines quoted from a failed run, and the seconds between two
// progress lines while a run lasts.
constexpr std::size_t kReasonLines = 3;
constexpr int kProgressSeconds = 10;

std::string read_tail(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(p, ec);
  if (!ec && size > kLogLimit) in.seekg(static_cast<std::streamoff>(size - kLogLimit));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The level of a log line "[12:00:00.000] [name] [level] text", or "" when
// it is not one.
std::string level_of(const std::string& line) {
  std::size_t at = 0;
  for (int field = 0; field < 3; ++field) {
    if (at >= line.size() || line[at] != '[') return "";
    const std::size_t end = line.find(']', at);
    if (end == std::string::npos) return "";
    if (field == 2) return line.substr(at + 1, end - at - 1);
    at = end + 2;
  }
  return "";
}

// Prints "conform: WHAT: N s so far" on stderr every kProgressSeconds until
// destroyed.
class Ticker {
 public:
  explicit Ticker(std::string what) : what_(std::move(what)) {
    std::fprintf(stderr, "conform: %s ...\n", what_.c_str());
    thread_ = std::thread([this] {
      const auto t0 = Clock::now();
      std::unique_lock lock(mutex_);
      while (!done_) {
        if (wake_.wait_for(lock, std::chrono::seconds(kProgressSeconds), [this] { return done_; }))
          break;
        const auto s = std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - t0);
        std::fprintf(stderr, "conform: %s: %lld s so far\n", what_.c_str(),
                     static_cast<long long>(s.count()));
      }
    });
  }
  ~Ticker() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  Ticker(const Ticker&) = delete;
  Ticker& operator=(const Ticker&) = delete;

 private:
  std::string what_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

// The whole case run by this program with the subject as ROLE, on `plane`;
// returns the run folder.
std::filesystem::path whole_run(const ConformOptions& o, const std::string& role,
                                const std::string& plane, const std::filesystem::path& out) {
  std::string cmd = quoted(o.master_program) + " run --scene " + quoted(o.scene_path) + " --case " +
                    quoted(o.case_name) + " --node " + quoted(role + "=" + o.address.str()) +
                    " --data-plane " + plane + " --out " + quoted((out / plane).string());
  if (!o.token_file.empty()) cmd += " --token-file " + quoted(o.token_file);
  const auto log = out / (plane + ".log");
  cmd += " </dev/null >" + quoted(log.string()) + " 2>&1";
  int status = 0;
  {
    const Ticker ticker("§17 the whole run on the " + plane + " plane");
    status = std::system(cmd.c_str());
  }
  if (status != 0)
    throw std::runtime_error("the " + plane +
                             " run failed: " + failure_reason(read_tail(log), status));
  return out / plane / o.case_name;
}

}  // namespace

std::string failure_reason(const std::string& log, int status) {
  std::deque<std::string> errors;
  std::string last;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    const std::string level = level_of(line);
    if (level == "error" || level == "critical" || level == "warning" ||
        line.rfind("master: ", 0) == 0) {
      errors.push_back(line);
      if (errors.size() > kReasonLines) errors.pop_front();
    } else if (level != "info" && level != "debug" && level != "trace") {
      last = line;
    }
  }
  std::string why;
  for (const std::string& e : errors) why += (why.empty() ? "" : " | ") + e;
  if (!why.empty()) return why;
  std::ostringstream s;
  if (status != -1 && WIFSIGNALED(status))
    s << "ended by signal " << WTERMSIG(status);
  else if (status != -1 && WIFEXITED(status))
    s << "exit status " << WEXITSTATUS(status);
  else
    s << "could not be started";
  s << ", and its output has no error line";
  if (!last.empty()) s << "; its last line: " << last;
  return s.str();
}

PrivateFolder::PrivateFolder(const std::string& parent, const std::string& prefix) {
  std::string name = (std::filesystem::path(parent) / (prefix + "XXXXXX")).string();
  std::vector<char> buffer(name.begin(), name.end());
  buffer.push_back('\0');
  if (::mkdtemp(buffer.data()) == nullptr)
    throw std::runtime_error("cannot make a private temporary folder in " + parent + ": " +
                             std::strerror(errno) + " (set TMPDIR to a folder you can write)");
  path_ = buffer.data();
}

PrivateFolder::~PrivateFolder() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string check_whole_runs(const ConformOptions& o, const std::string& role) {
  const PrivateFolder folder(std::filesystem::temp_directory_path().string(), "railcosim-conform-");
  const std::filesystem::path out = folder.path();
  const auto relay = whole_run(o, role, "relay", out);
  const auto direct = whole_run(o, role, "direct", out);
  if (read_all(direct / "summary.json").find("\"data_plane\": \"direct\"") == std::string::npos)
    return "skipped: the participant does not offer the direct plane";
  if (read_all(direct / "history.csv") != read_all(relay / "history.csv"))
    return "history.csv differs between the planes";
  return "";
}

}  // namespace railcosim::cli
