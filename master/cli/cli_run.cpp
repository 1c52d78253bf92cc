#include "cli/cli_run.hpp"

#include "cli/cli.hpp"

#include "engine/coupling_options.hpp"

#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "auth.hpp"
#include "cli/conform.hpp"
#include "cli/scene_coupling.hpp"
#include "cosim_case.hpp"
#include "log.hpp"
#include "model.hpp"
#include "remote/node_launcher.hpp"
#include "remote/peer_text.hpp"
#include "remote/remote_participant.hpp"
#include "remote/soil_check.hpp"
#include "remote/transport.hpp"
#include "run/execute.hpp"
#include "run/progress.hpp"
#include "run/run_output.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "scene_text.hpp"
#include "study/report.hpp"
#include "study/study.hpp"
#include "study/study_plan.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/stability.hpp"

namespace railcosim::cli {
namespace {

void print_summary(const run::RunRecord& r, const std::filesystem::path& dir) {
  std::printf("%s: %s", r.case_name.c_str(), r.status.c_str());
  if (r.rel_l2_error && r.case_name != "monolithic")
    std::printf(", rel. L2 error %.3e, max |error| %.3e m", *r.rel_l2_error, *r.max_abs_error_m);
  std::printf(", %ld macro steps,", r.macro_steps);
  for (const auto& [k, v] : r.micro_steps) std::printf(" %s %ld micro steps,", k.c_str(), v);
  std::printf(" wall %.3f s\n", r.wall_s);
  if (!r.message.empty()) std::printf("  %s\n", remote::terminal_text(r.message).c_str());
  std::printf("  results in %s\n", dir.string().c_str());
}

// The addresses the user gave for the participants of a case: --node
// ROLE=HOST:PORT, and --vehicle/--track for the vehicle and track roles.
std::map<std::string, Address> given_nodes(const RunArgs& a, const Scene& scene,
                                           const CaseSpec& spec) {
  std::map<std::string, Address> given;
  if (!a.vehicle.empty()) given["vehicle"] = parse_address(a.vehicle, "--vehicle");
  if (!a.track.empty()) given["track"] = parse_address(a.track, "--track");
  for (const std::string& n : a.nodes) {
    const auto eq = n.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--node " + n +
                                  ": expected ROLE=HOST:PORT, e.g. soil=127.0.0.1:7003");
    given[n.substr(0, eq)] = parse_address(n.substr(eq + 1), "--node " + n.substr(0, eq));
  }
  // An external soil is a program the master cannot start: its address must be given.
  // (A soil FMU named by the scene's [soil] table is hosted in process, or
  // served by an fmu_node the master starts.)
  if (scene.soil_model == "external" && !spec.monolithic && scene.fmu_mapping("soil").empty())
    for (const auto& p : partition(scene, spec))
      if (p.parts.has(Component::kSoil) && given.count(p.role) == 0)
        throw std::invalid_argument(
            "the scene's soil is external (soil.model = \"external\"): start its program and "
            "give its address with --node " +
            p.role + "=HOST:PORT" +
            (remote::is_remote_transport(a.transport) ? "" : " (and --transport tcp)"));
  // A soil the master starts is a program of its own too, reached over TCP.
  if (const OutsideSoil* soil = scene.started_soil();
      soil != nullptr && !spec.monolithic && !remote::is_remote_transport(a.transport))
    throw std::invalid_argument("the scene's soil is " + std::string(soil->title) +
                                " (soil.model = \"" + soil->model +
                                "\"), a program of its own that the master starts over TCP: use "
                                "--transport tcp (the default), not --transport inproc");
  if (given.empty()) return given;
  if (spec.monolithic)
    throw std::invalid_argument(
        "the monolithic case runs inside the master: it uses no nodes, so --node, --vehicle and "
        "--track do not apply");
  if (!remote::is_remote_transport(a.transport))
    throw std::invalid_argument("--node, --vehicle and --track need --transport tcp");
  std::string roles;
  const auto parts = partition(scene, spec);
  for (const auto& p : parts) roles += (roles.empty() ? "" : ", ") + p.role;
  std::map<std::string, std::string> served;  // address -> role: a node serves one participant
  for (const auto& entry : given) {
    // (clang 14 cannot capture a structured binding in a lambda)
    const std::string& role = entry.first;
    const Address& address = entry.second;
    if (std::none_of(parts.begin(), parts.end(), [&](const auto& p) { return p.role == role; }))
      throw std::invalid_argument("a node was given for the " + role + " participant (" +
                                  address.str() + "), but case " + spec.name() +
                                  " has none (its participants: " + roles + ")");
    if (const auto [at, fresh] = served.emplace(address.str(), role); !fresh)
      throw std::invalid_argument("the " + at->second + " and " + role +
                                  " participants were both given " + address.str() +
                                  ": a node serves one participant, give each its own address");
  }
  return given;
}

// Parses a case name; an unknown one is an error that lists this scene's cases.
CaseSpec parse_case_of(const std::string& name, const Scene& scene) {
  try {
    return parse_case(name);
  } catch (const std::invalid_argument& e) {
    std::string msg = e.what();
    msg += "; the cases of ";
    msg += scene.source;
    msg += " are:";
    for (const std::string& c : case_names(scene)) {
      msg += ' ';
      msg += c;
    }
    throw std::invalid_argument(msg);
  }
}

// The options of the run from the command line and the scene; checks that
// they fit each other and the case.
run::RunOptions run_options(const RunArgs& a, const Scene& scene, const CaseSpec& spec) {
  run::RunOptions o;
  o.macro_step = a.macro_step > 0 ? a.macro_step : scene.macro_step;
  o.tolerance = a.tolerance > 0 ? a.tolerance : scene.tolerance;
  o.feedthrough = *parse_feedthrough(a.feedthrough);
  o.coupling = a.c;
  o.coupling.method = engine::parse_coupling_method(a.coupling, "--coupling");
  o.coupling.inputs = engine::parse_input_mode(a.inputs, "--inputs");
  o.coupling.accelerator.kind = engine::parse_accelerator(a.accelerator, "--accelerator");
  check(o.coupling);
  o.data_plane = remote::parse_data_plane(a.data_plane);
  o.direct.window_steps = a.window_steps;
  o.judge.mode = verdict::parse_judge_mode(a.judge, "--judge");
  o.judge.budget = a.judge_budget;
  if (!spec.monolithic && !o.coupling.is_plain() && o.feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved applies to explicit coupling with held inputs only");
  if (a.macro_step > 0) {
    const double steps = scene.end_time / o.macro_step;
    if (std::abs(steps - std::round(steps)) > 1e-9 * steps)
      throw std::invalid_argument("--macro-step " + std::to_string(o.macro_step) +
                                  " does not divide the end time " +
                                  std::to_string(scene.end_time) + " s of " + scene.source);
  }
  check_case_for_scene(spec, scene);
  o.cut_windows = check_cut_windows(a, scene, spec, o.macro_step);
  if (!spec.monolithic) {
    try {
      run::check_whole_windows(scene, o, run::rate_plan(scene, spec, o));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(cut_windows_note(a, scene) + ": " + e.what());
    }
  }
  if (!spec.monolithic) remote::check_transport(o.coupling, a.transport);
  if (!spec.monolithic && spec.scheme == Scheme::kGaussSeidel &&
      o.feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument("--feedthrough resolved exists only for Jacobi schedules");
  return o;
}

// The coupling options of `master run`: explicit or implicit, the inputs,
// the accelerator and its numbers.
void add_coupling_options(CLI::App& run_command, RunArgs& a) {
  CLI::App* run = &run_command;
  run->add_option("--coupling", a.coupling,
                  "explicit (one pass per macro step, the paper) or implicit (each macro step "
                  "repeated from a checkpoint until the exchanged values converge)")
      ->check(CLI::IsMember({"explicit", "implicit"}))
      ->capture_default_str();
  run->add_option("--inputs", a.inputs,
                  "Inputs over a macro step: hold (zero-order hold), linear (ramp to the value "
                  "at the step's end where it is known), extrapolate1 or extrapolate2 (ramp to "
                  "a value extrapolated from past communication points; explicit only), "
                  "waveform0 to waveform3 (the sender's outputs at each of its micro steps, "
                  "interpolated with degree 0 to 3, where they are known: implicit iterations, "
                  "Gauss-Seidel's later participants; in process or over tcp on either data "
                  "plane, the direct one in lock step)")
      ->check(CLI::IsMember({"hold", "linear", "extrapolate1", "extrapolate2", "waveform0",
                             "waveform1", "waveform2", "waveform3"}))
      ->capture_default_str();
  run->add_option("--accelerator", a.accelerator,
                  "Implicit coupling: constant (under-relaxation), aitken or iqn-ils")
      ->check(CLI::IsMember(engine::accelerator_names()))
      ->capture_default_str();
  run->add_option("--relaxation", a.c.accelerator.relaxation,
                  "Implicit: the constant factor, and the first factor of aitken and iqn-ils")
      ->check(CLI::Range(1e-6, 1.0))
      ->capture_default_str();
  run->add_option("--max-iterations", a.c.max_iterations, "Implicit: iterations per macro step")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  run->add_option("--iteration-budget", a.c.iteration_budget,
                  "Implicit: iterations over the whole run; a run that spends them stops "
                  "not_converged (0: 50 per macro step of the run, which a run at the default "
                  "--max-iterations never spends)")
      ->check(CLI::Range(0L, 10'000'000'000L))
      ->capture_default_str();
  run->add_option("--convergence", a.c.convergence,
                  "Implicit: a macro step has converged when, for every exchanged quantity, "
                  "||G(x) - x|| <= this x the largest norm the quantity has had in the run (a "
                  "velocity: or its displacement's / H)")
      ->check(CLI::Range(1e-15, 0.5))
      ->capture_default_str();
  run->add_option("--reused-windows", a.c.accelerator.windows_reused,
                  "Implicit, iqn-ils: past macro steps whose iterations are reused")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
}

}  // namespace

void add_run_command(CLI::App& app, RunArgs& a) {
  CLI::App* run = app.add_subcommand("run",
                                     "Run one case and write DIR/CASE/{deflection.csv, "
                                     "history.csv, summary.json}");
  run->add_option("--scene", a.scene_path, "Scene file (TOML), e.g. scenes/paper.toml")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--case", a.case_name,
                  "Case to run: monolithic, or CUT-TYPE[+CUT-TYPE...]-SCHEME with CUT wr "
                  "(wheel/rail), rs (rail/sleepers) or ss (sleepers/soil), TYPE xx or xt, SCHEME "
                  "jacobi or gauss-seidel; e.g. rs-xx-jacobi, wr-xt+ss-xx-gauss-seidel")
      ->required();
  add_macro_step_option(*run, a);
  run->add_option("--tolerance", a.tolerance,
                  "Local error bound of a micro step in metres (default: "
                  "simulation.tolerance of the scene)")
      ->check(CLI::PositiveNumber);
  run->add_option("--feedthrough", a.feedthrough,
                  "When S1's force output is read in Jacobi X-T: lagged (end of its last step) "
                  "or resolved (after it received the fresh displacement)")
      ->check(CLI::IsMember({"lagged", "resolved"}))
      ->capture_default_str();
  run->add_option("--restart", a.restart,
                  "At communication points: consistent (restart from the acceleration the new "
                  "inputs imply) or carry (keep the integrator's); default: simulation.restart "
                  "of the scene, else consistent")
      ->check(CLI::IsMember({"consistent", "carry"}));
  add_coupling_options(*run, a);
  run->add_option("--transport", a.transport,
                  "inproc: every participant inside the master (an FMU the scene maps too); tcp: "
                  "each in its own node process")
      ->check(CLI::IsMember(remote::transport_names()))
      ->capture_default_str();
  run->add_option("--data-plane", a.data_plane,
                  "tcp: direct (explicit coupling with held inputs: the nodes send each other "
                  "their data, the master grants windows of macro steps and takes their "
                  "reports; implicit coupling and ramped inputs: lock step, one frame per node "
                  "and iteration, checkpoints kept by the nodes; when every node offers it) or "
                  "relay (every value and checkpoint through the master's event-driven relay)")
      ->check(CLI::IsMember({"direct", "relay"}))
      ->capture_default_str();
  run->add_option("--window-steps", a.window_steps,
                  "Direct data plane: macro steps per window (0: the whole run in one window)")
      ->check(CLI::Range(0L, 1000000000L))
      ->capture_default_str();
  run->add_option("--step-budget", a.step_budget,
                  "tcp: the most one macro step may take, in seconds, while its node shows "
                  "progress (a node silent for the step deadline fails sooner)")
      ->check(seconds_in(0.1, 86400.0))
      ->capture_default_str();
  run->add_option("--step-deadline-floor", a.step_deadline_floor,
                  "tcp: the least a macro step is waited for while its node is silent, in "
                  "seconds, on both data planes (the deadline is 50 times the slowest step so "
                  "far, within [this, 30 s]; raise it for a participant whose steps vary)")
      ->check(seconds_in(0.1, 86400.0))
      ->capture_default_str();
  add_judge_options(run, a);
  run->add_option("--node", a.nodes,
                  "ROLE=HOST:PORT of a running node serving that participant (vehicle, track, "
                  "rail, soil); repeatable. Participants without one get a node started here")
      ->take_all();
  run->add_option("--vehicle", a.vehicle,
                  "HOST:PORT of a running vehicle_node (= --node vehicle=...)");
  run->add_option("--track", a.track, "HOST:PORT of a running track_node (= --node track=...)");
  run->add_option("--reference-step", a.reference_step,
                  "Macro step of the co-simulation reference a run is judged against where no "
                  "monolithic one can be built (a --node participant, an external soil), s; "
                  "default: half the run's. On a scene whose soil the master starts (FE, "
                  "Green's functions) it asks for that judgement, and the soil then writes no "
                  "measures into the run's folder")
      ->check(CLI::PositiveNumber);
  run->add_option("--out", a.out, "Output folder; the run writes OUT/CASE/")->capture_default_str();
  run->add_option("--token-file", a.token_file, "Shared secret of nodes started with --token-file")
      ->check(CLI::ExistingFile);
  run->footer(scene_coupling_help());
  add_check_flag(*run, a.check);
  add_verbose_flag(*run);
  a.command = run;
}

// master --check run: what the run would be, once every input is read.
int print_check(const RunArgs& a, const Scene& scene, const CaseSpec& spec,
                const run::RunOptions& o, const std::map<std::string, Address>& given) {
  if (!a.token_file.empty()) read_token_file(a.token_file);
  std::string where = spec.monolithic ? "in process" : "over " + a.transport;
  if (!spec.monolithic && remote::is_remote_transport(a.transport))
    where += " (" + a.data_plane + " data plane)";
  for (const auto& [role, address] : given) where += ", " + role + " at " + address.str();
  std::printf("check: would run %s of %s (H = %g s, tolerance %g m, %s coupling) %s; writing %s\n",
              spec.name().c_str(), scene.source.c_str(), o.macro_step, o.tolerance,
              a.coupling.c_str(), where.c_str(),
              (std::filesystem::path(a.out) / spec.name()).string().c_str());
  return 0;
}

int do_run(const RunArgs& command_line) {
  auto log = logger("master");
  Scene scene = load_scene(command_line.scene_path);
  // The scene's [coupling] stands in for the flags not given.
  const RunArgs a = with_scene_coupling(command_line, scene);
  if (!a.restart.empty()) scene = with_keys(scene, {{"simulation.restart", a.restart}});
  const CaseSpec spec = parse_case_of(a.case_name, scene);
  run::RunOptions o;
  try {
    o = run_options(a, scene, spec);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(e.what() + scene_coupling_note(command_line, scene));
  }
  const std::map<std::string, Address> given = given_nodes(a, scene, spec);
  // A soil the master starts: would it accept its configuration? (Its ranks
  // and mesh limits, named by file and key, before a rank is started; at its own window.)
  if (given.count("soil") == 0)
    remote::check_started_soil(scene, spec, run::participant_step(scene, spec, o, "soil"));
  if (a.check) return print_check(a, scene, spec, o, given);

  remote::NodePool pool(a.token_file);  // nodes it starts share the secret of the given ones
  run::RunJob job;
  job.scene = &scene;
  job.spec = spec;
  job.options = o;
  job.options.stop = stop_flag();
  job.transport = a.transport;
  job.nodes = {given, &pool, {}};
  job.nodes.step_budget = std::chrono::milliseconds(std::lround(a.step_budget * 1000));
  job.nodes.step_deadline_floor =
      std::chrono::milliseconds(std::lround(a.step_deadline_floor * 1000));
  if (!a.token_file.empty()) job.nodes.token = read_token_file(a.token_file);
  job.out = a.out;
  job.folder = spec.name();
  job.reference_step = a.reference_step;
  run::RunRecord reference;
  job.reference = [&]() -> const run::RunRecord& {
    log->info("{}: computing the monolithic reference (H = {} s, tolerance = {} m)", spec.name(),
              o.macro_step, o.tolerance);
    reference = run::run_monolithic(scene, o);
    return reference;
  };
  // It writes its measures next to the run's files, unless the run is
  // judged against a co-simulation reference, whose runs would overwrite them.
  if (scene.started_soil() != nullptr) {
    const bool judged = a.reference_step > 0;
    job.on_folder = [&pool, &scene, judged](const std::filesystem::path& dir) {
      pool.use_fe_soil({scene.soil_ranks, judged ? "" : std::filesystem::absolute(dir).string(),
                        scene.started_soil(), scene.source});
    };
  }
  auto progress = std::make_shared<run::Progress>(spec.name(), 1, 1);
  job.on_progress = [progress, name = spec.name()](long done, long total) {
    progress->step(0, name, done, total);
  };
  const run::RunOutcome outcome = run::execute(job);
  progress->run_done(0);
  progress->end();
  if (outcome.error.empty()) print_summary(outcome.record, outcome.dir);
  if (const std::string& error = outcome.failure(); !error.empty()) {
    // A folder that could not be made (a full disk) holds nothing to point at.
    const std::string where = outcome.dir.empty()
                                  ? "no history or summary could be written under " +
                                        (std::filesystem::path(a.out) / spec.name()).string()
                                  : "history so far and summary in " + outcome.dir.string();
    std::fprintf(stderr, "master: %s failed: %s\n  %s\n", spec.name().c_str(),
                 remote::terminal_text(error).c_str(), where.c_str());
    return 1;
  }
  return 0;
}

}  // namespace railcosim::cli
