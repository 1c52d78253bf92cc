// Where the participants of a co-simulation live: in the master, or on
// nodes, either already running where the user says or started here on
// loopback, one per participant role.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "connection.hpp"
#include "participant.hpp"
#include "remote/node_launcher.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim {

// The node program that serves a role by default ("vehicle" -> vehicle_node;
// the rail alone is served by track_node --role rail).
std::string node_program(const std::string& role);

// How the master starts the FE soil (fe_soil/participant.py): under
// /usr/bin/python3, with `mpirun -n RANKS` when ranks > 1, the fe_soil
// package found in the source tree the master was built from (or in
// $RAILCOSIM_FE_SOIL, a folder holding fe_soil/ and sdk/python/). It
// writes its vibration measures into `output_dir`.
struct FeSoilLaunch {
  int ranks = 1;
  std::string output_dir;
};
LaunchCommand fe_soil_command(const FeSoilLaunch& fe, const std::string& token_file);
// The FE soil may take this long to print its address (Python and dolfinx
// load; the first run on a machine also compiles its forms), and to answer
// Configure and Statics (a mesh is built, the static solver set up).
inline constexpr std::chrono::seconds kFeSoilStart{120};
inline constexpr std::chrono::seconds kFeSoilReply{300};
// Meanwhile the other nodes hear nothing from the master: those it starts
// beside the FE soil wait this long before they close a silent session
// (--idle-timeout; 60 s by default).
inline constexpr std::chrono::seconds kIdleBesideFeSoil{360};

// Nodes started on loopback on demand, one per role, kept for the runs that
// follow (each node serves its sessions one after another).
class NodePool {
 public:
  // With a `token_file`, the nodes it starts require that shared secret.
  explicit NodePool(std::string token_file = "") : token_file_(std::move(token_file)) {}
  const Address& address(const std::string& role);
  // The soil role is then served by the FE soil, started on first use.
  void use_fe_soil(FeSoilLaunch fe) { fe_ = std::move(fe); }

 private:
  std::string token_file_;
  std::optional<FeSoilLaunch> fe_;
  std::map<std::string, std::unique_ptr<LaunchedNode>> nodes_;
};

// Makes the participant for one side (in-process, or a proxy to a node).
using ParticipantFactory = std::function<std::unique_ptr<Participant>(const SubsystemConfig&)>;

ParticipantFactory inproc_factory(const Scene& scene);

struct Transport {
  std::string name;  // "inproc" or "tcp"
  ParticipantFactory factory;
};

Transport inproc_transport(const Scene& scene);
// Over TCP: a participant whose role is in `given` connects there, any other
// to a node of `pool` (which must outlive the transport).
Transport tcp_transport(const Scene& scene, std::map<std::string, Address> given, NodePool& pool,
                        std::optional<std::string> token = std::nullopt);

}  // namespace railcosim
