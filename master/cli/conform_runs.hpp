// The conformance kit's whole runs (docs/protocol.md §17): the case run
// twice by this program with the participant as its role, relayed and on
// the direct data plane, compared bit for bit. The runs write into a private
// temporary folder (mkdtemp, mode 0700, removed afterwards), print a
// progress line on stderr while they last, and a run that fails is reported
// by its own error lines, never by its informational log.
#pragma once

#include <chrono>
#include <string>

#include "cli/conform.hpp"

namespace railcosim::cli {

// "" when the direct run's history equals the relayed run's, "skipped: ..."
// when the participant does not offer the direct plane, else why not.
std::string check_whole_runs(const ConformOptions& o, const std::string& role);

// Why a run whose output is `log` and whose exit status was `status` failed:
// its error lines (the master's "master: ..." lines and log lines of level
// error, critical or warning), at most the last few, else the exit status
// and the last line that is not an informational or debug log line.
std::string failure_reason(const std::string& log, int status);

// The folder the whole runs write into: a new one from mkdtemp under
// `parent` (mode 0700), removed with all it holds when this is destroyed.
class PrivateFolder {
 public:
  explicit PrivateFolder(const std::string& parent, const std::string& prefix);
  ~PrivateFolder();
  PrivateFolder(const PrivateFolder&) = delete;
  PrivateFolder& operator=(const PrivateFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace railcosim::cli
