// fmu_node: serves an FMU (FMI 2.0 or 3.0 co-simulation) as a participant.
//   fmu_node --config FILE [--table NAME] [--role ROLE] [--listen HOST:PORT] ...
// FILE's table names the FMU and maps its variables to the interfaces the
// master describes (fmu_participant.hpp, docs/fmu.md). The FMU's binary runs
// in this process with the user's rights.
#include <memory>

#include "fmu_participant.hpp"
#include "server.hpp"

int main(int argc, char** argv) {
  railcosim::NodeProgram program;
  program.name = "fmu_node";
  program.default_role = "any";
  program.configure = [](const railcosim::ParticipantSetup& setup) {
    return std::make_unique<railcosim::FmuParticipant>(setup);
  };
  return railcosim::node_main(program, argc, argv);
}
