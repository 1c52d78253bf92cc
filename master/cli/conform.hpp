// `master conform`: the protocol's checklist run against one participant
// that serves at HOST:PORT (docs/protocol.md §18), item by item, each with
// the section of the protocol document it tests: hello and its refusals,
// authentication, BUSY, configure, statics, initialize, relayed steps,
// bitwise save/restore, replies within a deadline, inputs never sent before
// (conform_fresh.hpp: what a replay of recorded replies fails), refusal of bad inputs,
// results and shutdown, and a whole run on the direct data plane against
// the same run relayed.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "connection.hpp"

namespace CLI {
class App;
}

namespace railcosim::cli {

struct ConformOptions {
  std::string scene_path;                 // the scene the participant is checked with
  std::string role;                       // vehicle, track, rail or soil
  Address address;                        // where it serves
  std::string case_name;                  // empty: a one-cut case of the role (conform_case)
  std::optional<std::string> token;       // its shared secret, if it has one
  std::string token_file;                 // the file it was read from
  std::chrono::milliseconds reply{1000};  // the slowest reply allowed in the checks
  long steps = 20;                        // macro steps of the relayed check
  std::string master_program;             // this program, for the whole runs of the last item
  std::uint64_t seed = 0;                 // of the inputs never sent before (0: a random one)
};

struct ConformItem {
  std::string section;  // "§4"
  std::string what;     // "hello: a wrong protocol version is refused"
  enum class Verdict { kPass, kFail, kSkipped } verdict = Verdict::kPass;
  std::string detail;  // why it failed or was skipped
};

// The case a role is checked in when none is given: a one-cut Jacobi X-X
// case in which the role is a participant (X-T for the soil of a scene on
// the FE soil, which serves ss-xt only).
std::string conform_case(const std::string& role, const std::string& soil_model = "");

// Runs every item, in order; a failed item does not stop the others.
// Throws std::runtime_error only when the checks cannot start (scene, case).
std::vector<ConformItem> run_conformance(const ConformOptions& options);

// Prints one line per item and a closing "N passed, N failed, N skipped";
// returns 0 when nothing failed, 1 otherwise.
int report_conformance(const std::vector<ConformItem>& items, const ConformOptions& options);

// The command line: `master conform --scene FILE --node ROLE=HOST:PORT ...`.
struct ConformArgs {
  CLI::App* command = nullptr;
  std::string scene_path, node, case_name, token_file;
  long reply_ms = 1000;
  long steps = 20;
  std::uint64_t seed = 0;
  bool check = false;  // master --check: read the options, connect to nothing
};
void add_conform_command(CLI::App& app, ConformArgs& args);
// Runs the checks and prints them; the exit status (0: nothing failed).
int do_conform(const ConformArgs& args);

}  // namespace railcosim::cli
