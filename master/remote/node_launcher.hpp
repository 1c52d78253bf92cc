// Starts a node program on loopback for the master, reads its
// "listening on HOST:PORT" line, and stops it when done.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

#include "connection.hpp"

namespace railcosim::remote {

// A program to start that is not a node program next to the master (the FE
// soil: a Python participant, perhaps under mpirun).
struct LaunchCommand {
  std::string name;               // in messages, e.g. "the FE soil"
  std::vector<std::string> argv;  // argv[0]: the program's absolute path
  std::vector<std::string> env;   // NAME=VALUE, set in the child (others inherited)
};

class LaunchedNode {
 public:
  // Starts `command`, which must print "listening on HOST:PORT" as its first
  // line within `timeout`. Throws std::runtime_error otherwise.
  LaunchedNode(const LaunchCommand& command, std::chrono::milliseconds timeout);
  // Starts `program` (a node program, looked up next to the running master)
  // with --listen 127.0.0.1:0 (and --role ROLE when a role is given). Throws
  // std::runtime_error if it does not print its address within `timeout`.
  // With a `token_file`, the node requires that shared secret too (so that
  // nodes the user started with it accept its peer links).
  // `extra`: further options for the node program.
  LaunchedNode(const std::string& program, std::chrono::milliseconds timeout,
               const std::string& listen = "127.0.0.1:0", const std::string& role = "",
               const std::string& token_file = "", const std::vector<std::string>& extra = {});
  ~LaunchedNode();  // SIGTERM, then SIGKILL if it does not exit within 2 s
  LaunchedNode(const LaunchedNode&) = delete;
  LaunchedNode& operator=(const LaunchedNode&) = delete;

  const Address& address() const { return address_; }
  pid_t pid() const { return pid_; }

 private:
  void start(const LaunchCommand& command, std::chrono::milliseconds timeout);
  std::string program_;
  pid_t pid_ = -1;
  Address address_;
};

// This process's environment with `overrides` (NAME=VALUE each) set: what
// a started program gets.
std::vector<std::string> child_environment(const std::vector<std::string>& overrides);

// What execve() takes to start `command`: its argv and its environment (the
// strings they point into are held here; built before a fork, the child
// only calls async-signal-safe functions).
struct ExecArgs {
  explicit ExecArgs(const LaunchCommand& command);
  ExecArgs(const ExecArgs&) = delete;
  ExecArgs& operator=(const ExecArgs&) = delete;
  std::vector<std::string> env_text;
  std::vector<const char*> argv, envp;
};

// The folder of the running executable (where the node programs are built).
std::string own_directory();

}  // namespace railcosim::remote
