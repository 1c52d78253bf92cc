// cpp_soil: serves the soil participant with this program's own physics.
//   cpp_soil --config FILE [--listen HOST:PORT] [--token-file FILE] ...
// (--help lists every option; FILE's [soil] table is the soil's own model.)
// Everything else (command line, framing, authentication, both data planes,
// implicit iterations, errors) is the package's node_main.
#include <memory>

#include "lumped_soil.hpp"
#include "server.hpp"

int main(int argc, char** argv) {
  railcosim::NodeProgram program;
  program.name = "cpp_soil";
  program.default_role = "soil";
  program.configure = [](const railcosim::ParticipantSetup& setup) {
    return std::make_unique<LumpedSoil>(setup);
  };
  return railcosim::node_main(program, argc, argv);
}
