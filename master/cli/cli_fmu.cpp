// `master fmu check FILE.fmu`: its command line; the check is fmu_check.cpp.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "archive.hpp"
#include "cli/cli.hpp"
#include "cli/fmu_check.hpp"
#include "fmu.hpp"
#include "fmu_error.hpp"

namespace railcosim::cli {

void add_fmu_command(CLI::App& app, FmuArgs& a) {
  a.command = app.add_subcommand("fmu", "Functional Mock-up Units (FMI 2.0 and 3.0 co-simulation)");
  a.command->require_subcommand(1);
  a.check_command = a.command->add_subcommand(
      "check",
      "Check an FMU: list its variables and capabilities, run its default experiment, repeat a "
      "step from a saved state bit for bit, and say which couplings it can take part in. The "
      "FMU's binary is native code that runs with your rights: check only FMUs you trust");
  a.check_command->add_option("FILE", a.file, "The .fmu file")->required();
  a.check_command
      ->add_option("--reference", a.reference,
                   "A record of the FMU's outputs to hold its default experiment against: a "
                   "CSV whose header names \"time\" and then variables (as the FMI reference "
                   "models' <model>_ref.csv); each row at a communication point is compared")
      ->check(CLI::ExistingFile);
  a.check_command
      ->add_option("--rtol", a.rtol,
                   "The reference's tolerance, relative to each column's largest |value|")
      ->default_val(1e-5)
      ->check(CLI::PositiveNumber);
  add_check_flag(*a.check_command, a.check);
}

int do_fmu(const FmuArgs& a) {
  try {
    if (a.check) {
      // Unpacked and read, the binary looked for, not loaded: no code of the FMU runs.
      const fmu::UnpackedArchive unpacked(a.file);
      const fmu::ModelDescription d =
          fmu::read_model_description(unpacked.root() / "modelDescription.xml");
      const auto so = std::filesystem::path("binaries") / fmu::platform_folder(d.version) /
                      (d.model_identifier + ".so");
      if (!std::filesystem::is_regular_file(unpacked.root() / so))
        throw fmu::FmuError(a.file + ": no binary for this platform (" + so.string() + ")");
      std::printf("check: would check FMU %s (FMI %s, %s, %zu variables)\n", a.file.c_str(),
                  fmu::version_name(d.version), so.c_str(), d.variables.size());
      if (!a.reference.empty()) {
        const ReferenceTable t = read_reference_csv(a.reference);
        std::printf("check: and hold it against %s (%zu rows, %zu columns)\n",
                    a.reference.c_str(), t.times.size(), t.names.size());
      }
      return 0;
    }
    FmuCheckOptions o;
    o.reference = a.reference;
    o.rtol = a.rtol;
    return print_fmu_check(check_fmu(a.file, o));
  } catch (const fmu::FmuError& e) {
    std::fprintf(stderr, "master fmu check: refused: %s\n", e.what());
    return 2;
  }
}

}  // namespace railcosim::cli
