// cpp_soil: serves the soil participant with this program's own physics.
// Everything else (command line, framing, authentication, both data planes,
// implicit iterations, errors) is the package's node_main.
#include <memory>

#include "lumped_soil.hpp"
#include "server.hpp"

int main(int argc, char** argv) {
  railcosim::NodeProgram program;
  program.name = "cpp_soil";
  program.default_role = "soil";
  program.make_participant = [](const railcosim::Scene& scene,
                                const railcosim::SubsystemConfig& config) {
    return std::make_unique<LumpedSoil>(scene, config);
  };
  return railcosim::node_main(program, argc, argv);
}
