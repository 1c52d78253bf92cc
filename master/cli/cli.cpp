#include "cli/cli.hpp"

#include <signal.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "cli/cli_keys.hpp"
#include "cli/cli_run.hpp"
#include "cli/cli_study.hpp"
#include "cli/compare.hpp"
#include "cli/conform.hpp"
#include "cli/fmu_check.hpp"
#include "log.hpp"
#include "remote/peer_text.hpp"
#include "remote/remote_participant.hpp"
#include "scene.hpp"

namespace railcosim::cli {
namespace {

// Set by SIGINT/SIGTERM: runs stop at the next macro step and leave a
// summary saying so.
std::atomic<int> g_stop{0};

void on_signal(int sig) {
  g_stop.store(sig);
}

void catch_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  set_interrupt_flag(&g_stop);  // a wait on a node ends too
}

}  // namespace

CLI::Validator seconds_in(double lo, double hi) {
  std::ostringstream range;
  range << lo << " to " << hi;
  return CLI::Validator(
      [lo, hi, r = range.str()](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !(v >= lo && v <= hi))
          return "expected seconds from " + r + ", got " + text;
        return "";
      },
      "SECONDS in [" + range.str() + "]");
}

void add_check_flag(CLI::App& command, bool& check) {
  command.add_flag("--check", check,
                   "Read the command line and the files it names (scene, secret, node addresses) "
                   "as the command would, print what it would do, and stop: no node is started, "
                   "no run made, no file written");
}

void add_verbose_flag(CLI::App& command) {
  command.add_flag_callback(
      "--verbose", [] { logger("master")->set_level(spdlog::level::debug); },
      "Also log the master's details on stderr: the nodes it starts, where they listen, the "
      "coupled static state");
}

const std::atomic<int>* stop_flag() {
  return &g_stop;
}

int master_main(int argc, char** argv) {
  CLI::App app{
      "Vehicle/track co-simulation master: runs the monolithic reference or a "
      "co-simulation case of a scene."};
  app.require_subcommand(1);
  RunArgs ra;
  add_run_command(app, ra);
  StudyArgs sa;
  add_study_command(app, sa);
  ConformArgs ca;
  add_conform_command(app, ca);
  KeysArgs ka;
  add_keys_command(app, ka);
  CompareArgs cmp;
  add_compare_command(app, cmp);
  FmuArgs fa;
  add_fmu_command(app, fa);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    catch_stop_signals();
    if (*ra.command) return do_run(ra);
    if (*sa.command) return do_study(sa);
    if (*ca.command) return do_conform(ca);
    if (*ka.command) return do_keys(ka);
    if (*cmp.command) return do_compare(cmp);
    if (*fa.command) return do_fmu(fa);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "master: scene error: %s\n", remote::terminal_text(e.what()).c_str());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "master: %s\n", remote::terminal_text(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "master: run failed: %s\n", remote::terminal_text(e.what()).c_str());
    return 1;
  }
  return 0;
}

}  // namespace railcosim::cli
