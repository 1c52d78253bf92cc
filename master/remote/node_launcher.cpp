#include "remote/node_launcher.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <vector>

namespace railcosim::remote {

namespace {

// SIGTERM (mpirun passes it on to its ranks), then SIGKILL if the program
// has not exited within 2 s.
void stop(pid_t pid) {
  ::kill(pid, SIGTERM);
  for (int i = 0; i < 200; ++i) {
    if (::waitpid(pid, nullptr, WNOHANG) == pid) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
}

}  // namespace

std::vector<std::string> child_environment(const std::vector<std::string>& overrides) {
  std::vector<std::string> env;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry = *e;
    bool replaced = false;
    for (const std::string& mine : overrides)
      replaced = replaced || entry.compare(0, mine.find('=') + 1, mine, 0, mine.find('=') + 1) == 0;
    if (!replaced) env.push_back(entry);
  }
  env.insert(env.end(), overrides.begin(), overrides.end());
  return env;
}

ExecArgs::ExecArgs(const LaunchCommand& command) : env_text(child_environment(command.env)) {
  for (const std::string& a : command.argv) argv.push_back(a.c_str());
  argv.push_back(nullptr);
  for (const std::string& e : env_text) envp.push_back(e.c_str());
  envp.push_back(nullptr);
}

std::string own_directory() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return ".";
  return exe.parent_path().string();
}

LaunchedNode::LaunchedNode(const std::string& program, std::chrono::milliseconds timeout,
                           const std::string& listen, const std::string& role,
                           const std::string& token_file, const std::vector<std::string>& extra)
    : program_(program) {
  const std::string path = own_directory() + "/" + program;
  if (::access(path.c_str(), X_OK) != 0)
    throw std::runtime_error(
        "cannot start " + path + ": " + std::strerror(errno) +
        " (build it, or start the nodes yourself and pass --node ROLE=HOST:PORT)");
  LaunchCommand c{program, {path, "--listen", listen, "--log-level", "warn"}, {}};
  if (!role.empty()) c.argv.insert(c.argv.end(), {"--role", role});
  if (!token_file.empty()) c.argv.insert(c.argv.end(), {"--token-file", token_file});
  c.argv.insert(c.argv.end(), extra.begin(), extra.end());
  start(c, timeout);
}

LaunchedNode::LaunchedNode(const LaunchCommand& command, std::chrono::milliseconds timeout)
    : program_(command.name) {
  if (command.argv.empty() || ::access(command.argv[0].c_str(), X_OK) != 0)
    throw std::runtime_error("cannot start " + command.name + ": " +
                             (command.argv.empty()
                                  ? std::string("no program")
                                  : command.argv[0] + ": " + std::strerror(errno)));
  start(command, timeout);
}

void LaunchedNode::start(const LaunchCommand& command, std::chrono::milliseconds timeout) {
  const std::string& program = command.name;
  const ExecArgs exec(command);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const pid_t parent = ::getpid();
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid_ == 0) {
    // The node must not outlive the master that started it.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(1);
    ::dup2(fds[1], STDOUT_FILENO);
    ::execve(exec.argv[0], const_cast<char* const*>(exec.argv.data()),
             const_cast<char* const*>(exec.envp.data()));
    ::_exit(127);
  }
  ::close(fds[1]);

  // Read the first line, up to the deadline.
  std::string line;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (line.find('\n') == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    pollfd p{fds[0], POLLIN, 0};
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
    char buf[256];
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n <= 0) break;
    line.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  const std::string prefix = "listening on ";
  const auto nl = line.find('\n');
  if (nl == std::string::npos || line.rfind(prefix, 0) != 0) {
    stop(pid_);
    pid_ = -1;
    throw std::runtime_error(program + " did not report its address within " +
                             std::to_string(timeout.count()) + " ms" +
                             (line.empty() ? "" : " (it printed: " + line.substr(0, nl) + ")"));
  }
  address_ = parse_address(line.substr(prefix.size(), nl - prefix.size()), program + " address");
}

LaunchedNode::~LaunchedNode() {
  if (pid_ > 0) stop(pid_);
}

}  // namespace railcosim::remote
