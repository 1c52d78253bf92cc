// The command line of every node program: options, limits, "listening on".
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "auth.hpp"
#include "log.hpp"
#include "server.hpp"

namespace railcosim {

int node_main(const std::string& default_role, int argc, char** argv) {
  return node_main(NodeProgram{default_role + "_node", default_role, {}, {}}, argc, argv);
}

namespace {

// Seconds from 1 ms to a day: what the millisecond clocks of the limits
// hold (NaN, 1e-300 and 1e300 are refused, not read as "no limit").
const CLI::Validator kSeconds(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !(v >= 1e-3 && v <= 86400.0))
        return "expected seconds from 0.001 to 86400, got " + text;
      return "";
    },
    "SECONDS in [0.001, 86400]");

// The values of the command line, at their defaults until parsed.
struct NodeCommandLine {
  std::string role;
  std::string listen = "127.0.0.1:0";
  std::string scene_path;
  std::size_t max_frame = kDefaultMaxFrameBytes;
  std::string level = "info";
  double idle_seconds = 60.0;
  double message_seconds = 10.0;
  double step_seconds = 30.0;
  long max_micro_steps = Newmark::kMaxStepsPerInterval;
  std::string token_file;
  std::string config_path;
  std::string config_table;
  bool check = false;
};

void declare_options(CLI::App& app, NodeCommandLine& o) {
  std::vector<std::string> choices = role_names();
  std::string listed;
  for (const std::string& r : choices) listed += r + ", ";
  choices.emplace_back("any");
  app.add_option(
         "--role", o.role,
         "The participant this node serves: " + listed + "or any (whatever the master asks for)")
      ->check(CLI::IsMember(choices))
      ->capture_default_str();
  app.add_option("--listen", o.listen, "HOST:PORT to listen on (port 0: the system chooses)")
      ->capture_default_str();
  app.add_option("--scene", o.scene_path,
                 "Scene file: when given, only a master running this very scene is accepted")
      ->check(CLI::ExistingFile);
  app.add_option("--max-frame-bytes", o.max_frame, "Largest frame accepted")->capture_default_str();
  app.add_option("--token-file", o.token_file,
                 "File holding a shared secret (16+ characters): a master must prove it knows it "
                 "before anything else. Required to listen on a non-loopback address")
      ->check(CLI::ExistingFile);
  app.add_option("--max-micro-steps", o.max_micro_steps,
                 "Micro steps a subsystem may take in one macro step before it gives up "
                 "(STEP_FAILED: the run diverges)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--idle-timeout", o.idle_seconds,
                 "Seconds a session may stay silent before the node closes it")
      ->check(kSeconds)
      ->capture_default_str();
  app.add_option("--message-timeout", o.message_seconds,
                 "Seconds a request may take to arrive whole once begun, and a reply to be read "
                 "whole (also the hello's deadline, when shorter)")
      ->check(kSeconds)
      ->capture_default_str();
  app.add_option("--max-step-seconds", o.step_seconds,
                 "Seconds of work one macro step may take before it fails (STEP_FAILED)")
      ->check(kSeconds)
      ->capture_default_str();
  app.add_option("--config", o.config_path,
                 "TOML file holding the participant's own configuration, in its table [--table]: "
                 "given to the participant at every session instead of the table the master's "
                 "scene sends (Configure.own_config)")
      ->check(CLI::ExistingFile);
  app.add_option("--table", o.config_table,
                 "The table of --config that is the configuration (default: the participant's "
                 "name, e.g. soil)");
  app.add_flag("--check", o.check,
               "Check the options (the address, the scene and secret files) as the node would, "
               "print what it would serve, and stop without listening");
  app.add_option("--log-level", o.level, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
      ->capture_default_str();
}

ServerLimits server_limits(const NodeCommandLine& o) {
  ServerLimits limits;
  limits.max_frame_bytes = o.max_frame;
  limits.idle_timeout = std::chrono::milliseconds(static_cast<long>(o.idle_seconds * 1000));
  limits.message_timeout = std::chrono::milliseconds(static_cast<long>(o.message_seconds * 1000));
  limits.max_step_time = std::chrono::milliseconds(static_cast<long>(o.step_seconds * 1000));
  limits.handshake_timeout =
      std::min({limits.handshake_timeout, limits.idle_timeout, limits.message_timeout});
  return limits;
}

// The file of --config, read and checked as a session will read it (its
// table, unless the node serves any participant: then at each session).
std::optional<ConfigFile> config_file(const NodeProgram& program, const NodeCommandLine& o) {
  if (o.config_path.empty()) {
    if (!o.config_table.empty()) throw std::invalid_argument("--table needs --config FILE");
    return std::nullopt;
  }
  if (!program.configure)
    throw std::invalid_argument("--config " + o.config_path + ": the " + program.name +
                                " program's participant takes no configuration of its own (the "
                                "built-in model reads the scene)");
  std::ifstream in(o.config_path, std::ios::binary);
  std::ostringstream text;
  if (!in || !(text << in.rdbuf()))
    throw std::invalid_argument("--config " + o.config_path + ": cannot be read");
  ConfigFile file{o.config_path, text.str(), o.config_table};
  const std::string table = o.config_table.empty() ? o.role : o.config_table;
  if (table != "any") (void)OwnConfig::table_of(file.text, file.path, table);
  return file;
}

// Checks the options, then serves sessions until the process is stopped.
void serve(const NodeProgram& program, const NodeCommandLine& o) {
  NodeOptions options;
  options.role = o.role;
  options.name = program.name;
  options.make_participant = program.make_participant;
  options.max_micro_steps = o.max_micro_steps;
  options.configure = program.configure;
  if (!o.scene_path.empty()) options.pinned_scene = load_scene(o.scene_path);
  options.config_file = config_file(program, o);
  const Address address = parse_address(o.listen, "--listen");
  if (!o.token_file.empty()) options.token = read_token_file(o.token_file);
  if (!options.token && !is_loopback(address.host))
    throw std::runtime_error(
        "refusing to listen on " + address.str() +
        " without --token-file: any host that reaches this address could drive the node. "
        "Share a secret with the master (--token-file on both), or listen on 127.0.0.1");
  if (o.check) {
    std::printf("check: would serve the %s participant on %s%s%s%s\n", o.role.c_str(),
                address.str().c_str(), options.token ? ", with a shared secret" : "",
                o.scene_path.empty() ? "" : (", pinned to " + o.scene_path).c_str(),
                o.config_path.empty() ? "" : (", configured by " + o.config_path).c_str());
    return;
  }
  NodeServer server(options, address, server_limits(o));
  std::printf("listening on %s\n", server.local_address().str().c_str());
  std::fflush(stdout);
  server.run(true);
}

}  // namespace

int node_main(const NodeProgram& program, int argc, char** argv) {
  CLI::App app{"Serves the " + program.default_role +
               " participant of a vehicle/track/soil co-simulation to a master, one session at a "
               "time."};
  NodeCommandLine options;
  options.role = program.default_role;
  declare_options(app, options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  spdlog::set_level(spdlog::level::from_str(options.level));
  try {
    serve(program, options);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program.name.c_str(), e.what());
    return 2;
  }
}

}  // namespace railcosim
