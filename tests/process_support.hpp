// Test helper: the master program run as a user runs it.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace railcosim::test {

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr together
};

// Runs `master ARGS` from the build's bin folder and waits for it.
inline Outcome run_master(const std::string& args) {
  const std::string cmd = std::string(RAILCOSIM_BIN_DIR) + "/master " + args + " 2>&1";
  Outcome o;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return o;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p)) o.output += buf.data();
  const int st = pclose(p);
  o.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return o;
}

}  // namespace railcosim::test
