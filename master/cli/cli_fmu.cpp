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
      return 0;
    }
    return print_fmu_check(check_fmu(a.file));
  } catch (const fmu::FmuError& e) {
    std::fprintf(stderr, "master fmu check: refused: %s\n", e.what());
    return 2;
  }
}

}  // namespace railcosim::cli
