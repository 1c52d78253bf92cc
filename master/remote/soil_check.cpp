#include "remote/soil_check.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

#include "model.hpp"
#include "remote/node_launcher.hpp"
#include "remote/transport.hpp"
#include "subsystem.hpp"
#include "wire.hpp"

namespace railcosim::remote {
namespace {

struct Finished {
  int status = -1;     // the exit status; -1: it did not exit (see signal)
  int signal = 0;      // the signal that ended it; 0: none
  std::string errors;  // what it wrote on stderr (the first 64 KiB)
};

// What ended it, for a message: "it exited with status 3", "it was ended by
// signal 11 (Segmentation fault)", or no answer within the deadline.
std::string ending(const Finished& f, std::chrono::milliseconds timeout) {
  if (f.signal != 0)
    return "it was ended by signal " + std::to_string(f.signal) + " (" + ::strsignal(f.signal) +
           ")";
  if (f.status >= 0) return "it exited with status " + std::to_string(f.status);
  return "no answer within " + std::to_string(timeout.count()) + " ms";
}

// Runs `command` with `input` on its standard input in a process group of
// its own; waits for it to exit within `timeout` (else kills it). Once it
// has exited, or the deadline has passed, whatever is left of its group (a
// child it forked, which may hold its stderr open) is killed too.
Finished run_with_input(const LaunchCommand& command, const std::string& input,
                        std::chrono::milliseconds timeout) {
  const ExecArgs exec(command);
  int in[2], err[2];
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::setpgid(0, 0);
    ::dup2(in[0], STDIN_FILENO);
    ::dup2(err[1], STDERR_FILENO);
    ::execve(exec.argv[0], const_cast<char* const*>(exec.argv.data()),
             const_cast<char* const*>(exec.envp.data()));
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: the group exists before either goes on
  ::close(in[0]);
  ::close(err[1]);
  Finished f;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto left = [&] {
    return static_cast<int>(std::max<long long>(
        0, std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                 std::chrono::steady_clock::now())
               .count()));
  };
  bool exited = false;
  auto reap = [&] {  // true once it has exited, with how
    int status = 0;
    if (exited || ::waitpid(pid, &status, WNOHANG) != pid) return exited;
    exited = true;
    if (WIFEXITED(status)) f.status = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) f.signal = WTERMSIG(status);
    return true;
  };
  // The input, within the deadline too (a program that never reads it must
  // not hold the master past it); a program that exits first ends the write.
  ::fcntl(in[1], F_SETFL, O_NONBLOCK);
  const ::sighandler_t old = ::signal(SIGPIPE, SIG_IGN);
  for (std::size_t at = 0; at < input.size() && !reap();) {
    pollfd p{in[1], POLLOUT, 0};
    if (left() <= 0) break;
    if (::poll(&p, 1, std::min(left(), 50)) <= 0) continue;
    const ssize_t w = ::write(in[1], input.data() + at, input.size() - at);
    if (w < 0 && errno != EAGAIN && errno != EINTR) break;
    if (w > 0) at += static_cast<std::size_t>(w);
  }
  ::signal(SIGPIPE, old);
  ::close(in[1]);
  // Its stderr until it exits (checked every 50 ms: a child it forked may
  // keep the pipe open after it), then what is left in the pipe.
  bool reading = true;
  while (reading && left() > 0) {
    const bool done = reap();
    pollfd p{err[0], POLLIN, 0};
    if (::poll(&p, 1, done ? 0 : std::min(left(), 50)) <= 0) {
      if (done) break;
      continue;
    }
    char buf[4096];
    const ssize_t n = ::read(err[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) reading = false;
    if (n > 0 && f.errors.size() < (64u << 10)) f.errors.append(buf, static_cast<std::size_t>(n));
  }
  ::close(err[0]);
  // Closed stderr without having exited: it is about to, within the deadline.
  while (!reap() && left() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ::kill(-pid, SIGKILL);  // the group: it, if still running, and whatever it forked
  if (!exited) ::waitpid(pid, nullptr, 0);  // no answer in time: the status stays -1
  return f;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

}  // namespace

void check_started_soil(const Scene& scene, const CaseSpec& spec, double macro_step,
                        std::chrono::milliseconds timeout) {
  const OutsideSoil* soil = scene.started_soil();
  if (soil == nullptr || spec.monolithic) return;
  for (const ParticipantSpec& p : partition(scene, spec)) {
    if (p.role != "soil") continue;
    const SubsystemConfig c = subsystem_config(scene, p, macro_step, 0.0);
    const std::string input = configure_envelope(scene, c, false).configure().SerializeAsString();
    const LaunchCommand command = soil_check_command({1, "", soil, scene.source});
    const Finished f = run_with_input(command, input, timeout);
    if (f.status == 0) return;
    if (f.status == 2) {  // its reason names the key, and the file where it knows it
      const std::string why = trimmed(f.errors);
      throw std::invalid_argument(
          (why.rfind(scene.source + ": ", 0) == 0 ? "" : scene.source + ": ") + why + " (" +
          soil->title + " would refuse it)");
    }
    throw std::runtime_error("cannot check " + std::string(soil->title) + "'s configuration (" +
                             command.name + "): " + ending(f, timeout) +
                             (f.errors.empty() ? "" : ": " + trimmed(f.errors.substr(0, 2000))));
  }
}

}  // namespace railcosim::remote
