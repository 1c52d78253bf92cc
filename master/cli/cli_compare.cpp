// `master compare`: its command line, and the report of compare_runs()
// (compare.cpp).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "cli/cli.hpp"
#include "cli/compare.hpp"
#include "remote/peer_text.hpp"

namespace railcosim::cli {

void add_compare_command(CLI::App& app, CompareArgs& a) {
  a.command = app.add_subcommand(
      "compare",
      "Compare two runs' output folders value by value (deflection.csv, history.csv, soil.csv, "
      "soil_forces.csv, where REFERENCE has them): each column's largest "
      "difference over its largest magnitude in REFERENCE must be within --tolerance. Exit "
      "status 0: they agree; 1: they differ (or OTHER lacks a run, a file, a row); 2: a folder "
      "or file cannot be read");
  a.command
      ->add_option("REFERENCE", a.reference,
                   "A `master run --out` folder (one folder per case), or one run's folder")
      ->required()
      ->check(CLI::ExistingDirectory);
  a.command->add_option("OTHER", a.other, "The folder compared with it, laid out the same way")
      ->required()
      ->check(CLI::ExistingDirectory);
  a.command->add_option("--tolerance", a.tolerance, "The largest relative difference allowed")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  a.command
      ->add_option("--max-file-mb", a.max_file_mb,
                   "The largest file read, in MiB (a folder someone sends may hold anything); "
                   "a file over it is refused, named")
      ->check(CLI::Range(1e-6, 1e6))
      ->capture_default_str();
  add_check_flag(*a.command, a.check);
}

namespace {

std::string format_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

}  // namespace

int do_compare(const CompareArgs& a) {
  if (a.check) {
    std::printf("check: would compare %s with %s to %g relative\n", a.reference.c_str(),
                a.other.c_str(), a.tolerance);
    return 0;
  }
  const RunComparison r = compare_runs(a.reference, a.other, a.tolerance,
                                       static_cast<std::uintmax_t>(a.max_file_mb * 1048576.0));
  std::size_t over = 0;
  for (const FileComparison& f : r.files) {
    if (!f.problem.empty()) {
      std::printf("differ: %s: %s\n", f.name.c_str(), f.problem.c_str());
      ++over;
    } else if (!(f.worst <= r.tolerance)) {
      std::printf("differ: %s: column %s by %.3g relative\n", f.name.c_str(),
                  remote::terminal_text(f.worst_column).c_str(), f.worst);
      ++over;
    }
  }
  const FileComparison* w = r.worst();
  const std::string worst = w ? "worst relative difference " + format_number(w->worst) + " (" +
                                    w->name + ", column " + remote::terminal_text(w->worst_column) +
                                    ")"
                              : std::string("no file to compare");
  std::printf("%s: %zu run(s), %zu file(s), %zu over the tolerance %g; %s\n",
              r.agree() ? "agree" : "differ", r.runs, r.files.size(), over, r.tolerance,
              worst.c_str());
  return r.agree() ? 0 : 1;
}

}  // namespace railcosim::cli
