// `master conform`: its command line, and the run of the checklist
// (conform.cpp) it starts.
#include <CLI/CLI.hpp>
#include <cstdio>

#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "auth.hpp"
#include "cli/cli.hpp"
#include "cli/conform.hpp"
#include "remote/peer_text.hpp"
#include "scene.hpp"

namespace railcosim::cli {

void add_conform_command(CLI::App& app, ConformArgs& a) {
  a.command = app.add_subcommand(
      "conform",
      "Check a participant that serves at HOST:PORT against the protocol's checklist "
      "(docs/protocol.md §18): one line per item, PASS/FAIL/SKIP, with the section it tests");
  a.command->add_option("--scene", a.scene_path, "Scene file the participant is checked with")
      ->required()
      ->check(CLI::ExistingFile);
  a.command
      ->add_option("--node", a.node,
                   "ROLE=HOST:PORT of the participant (vehicle, track, "
                   "rail, soil)")
      ->required();
  a.command->add_option("--case", a.case_name,
                        "Case it is checked in (default: ss-xx-jacobi for soil, ss-xt-jacobi for "
                        "the FE soil, "
                        "wr-xx+rs-xx-jacobi for rail, wr-xx-jacobi otherwise)");
  a.command->add_option("--token-file", a.token_file, "Its shared secret, if it has one")
      ->check(CLI::ExistingFile);
  a.command
      ->add_option("--reply-ms", a.reply_ms,
                   "The slowest reply a check allows, ms (a participant slower than this "
                   "per macro step fails the deadline item)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  a.command->add_option("--steps", a.steps, "Macro steps of the relayed check")
      ->check(CLI::Range(4, 100000))
      ->capture_default_str();
  a.command
      ->add_option("--seed", a.seed,
                   "Seed of the inputs never sent before (0: a fresh one each run; a "
                   "failure prints the one it used)")
      ->capture_default_str();
  add_check_flag(*a.command, a.check);
}

int do_conform(const ConformArgs& a) {
  ConformOptions o;
  o.scene_path = a.scene_path;
  const auto eq = a.node.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("--node " + a.node + ": expected ROLE=HOST:PORT");
  o.role = a.node.substr(0, eq);
  o.address = parse_address(a.node.substr(eq + 1), "--node " + o.role);
  o.case_name =
      a.case_name.empty() ? conform_case(o.role, load_scene(a.scene_path).soil_model) : a.case_name;
  if (!a.token_file.empty()) {
    o.token = read_token_file(a.token_file);
    o.token_file = a.token_file;
  }
  o.reply = std::chrono::milliseconds(a.reply_ms);
  o.steps = a.steps;
  o.seed = a.seed;
  if (a.check) {
    std::printf("check: would check the %s participant at %s with case %s\n", o.role.c_str(),
                o.address.str().c_str(), o.case_name.c_str());
    return 0;
  }
  std::error_code ec;
  o.master_program = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  return report_conformance(run_conformance(o), o);
}

int report_conformance(const std::vector<ConformItem>& items, const ConformOptions& o) {
  int passed = 0, failed = 0, skipped = 0;
  std::printf("conformance of the %s participant at %s (%s, %s):\n", o.role.c_str(),
              o.address.str().c_str(), o.scene_path.c_str(), o.case_name.c_str());
  for (const ConformItem& i : items) {
    const char* v = i.verdict == ConformItem::Verdict::kPass   ? "PASS"
                    : i.verdict == ConformItem::Verdict::kFail ? "FAIL"
                                                               : "SKIP";
    (i.verdict == ConformItem::Verdict::kPass   ? passed
     : i.verdict == ConformItem::Verdict::kFail ? failed
                                                : skipped)++;
    // The detail may quote the participant's own words.
    std::printf("  %s  %-4s %s%s%s\n", v, i.section.c_str(), i.what.c_str(),
                i.detail.empty() ? "" : ": ", remote::terminal_text(i.detail).c_str());
  }
  std::printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
  return failed == 0 ? 0 : 1;
}

}  // namespace railcosim::cli
