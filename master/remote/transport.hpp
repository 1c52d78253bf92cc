// Where the participants of a co-simulation live: in the master, or on
// nodes, either already running where the user says or started here on
// loopback, one per participant role.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "connection.hpp"
#include "engine/coupling_options.hpp"
#include "participant.hpp"
#include "remote/node_launcher.hpp"
#include "remote/transport_names.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim::remote {

// The node program that serves a role by default ("vehicle" -> vehicle_node;
// the rail alone is served by track_node --role rail).
std::string node_program(const std::string& role);

// How the master starts a soil of its own (common/outside_soil.hpp: the FE
// soil, fe_soil/participant.py; the Green's-function soil,
// green_soil/participant.py): `python3 -m MODULE` under /usr/bin/python3,
// with `mpirun -n RANKS` when ranks > 1, the package found in the source
// tree the master was built from (or in $RAILCOSIM_FE_SOIL, a folder
// holding fe_soil/, green_soil/ and sdk/python/). It writes its vibration
// measures into `output_dir`, and names `scene` (the
// scene file) in its configuration errors.
struct FeSoilLaunch {
  int ranks = 1;
  std::string output_dir;
  const OutsideSoil* soil = &kOutsideSoils[0];  // which soil (the FE soil by default)
  std::string scene;
};
LaunchCommand fe_soil_command(const FeSoilLaunch& fe, const std::string& token_file);
// The PYTHONPATH the started soils get: `root` (the product's folder), then
// the absolute entries of the user's PYTHONPATH `user` in their order. Empty
// entries (what `export PYTHONPATH=/opt/x:$PYTHONPATH` leaves), "." and
// other relative ones are dropped: Python reads them from the working
// directory, so a numpy.py there would run in the soil.
std::string soil_python_path(const std::string& root, const std::string& user);
// The same program asked only to check a Configure on its standard input
// (--check-configure; one process, no MPI ranks, no port).
LaunchCommand soil_check_command(const FeSoilLaunch& fe);
// A started soil may take this long to print its address (Python and dolfinx
// load; the first run on a machine also compiles its forms), and to answer
// Configure and Statics (a mesh is built, the static solver set up; or the
// Green's functions computed: those of scenes/ground_vibration_train.toml
// took over 300 s on a loaded two-core machine).
inline constexpr std::chrono::seconds kFeSoilStart{120};
inline constexpr std::chrono::seconds kFeSoilReply{900};
// RAILCOSIM_REPLY_SECONDS, when set: the master's limit on every reply other
// than a step's (hello, configure, each statics, ...), for every participant
// over TCP, the soils it starts included; unset: nullopt (10 s, or
// kFeSoilReply). Throws std::invalid_argument for a value not in (0, 86400].
std::optional<std::chrono::milliseconds> reply_limit_override();
// Meanwhile the other nodes hear nothing from the master: those it starts
// beside the FE soil wait this long before they close a silent session
// (--idle-timeout; 60 s by default).
inline constexpr std::chrono::seconds kIdleBesideFeSoil{960};
static_assert(kIdleBesideFeSoil > kFeSoilReply,
              "the nodes beside a started soil must outwait its Configure and Statics");

// Nodes started on loopback on demand, one per role, kept for the runs that
// follow (each node serves its sessions one after another).
class NodePool {
 public:
  // With a `token_file`, the nodes it starts require that shared secret.
  explicit NodePool(std::string token_file = "") : token_file_(std::move(token_file)) {}
  // The node of `role`, started on first use: `program` (default: the
  // role's node program, node_program()) with --role where its name is not
  // the role's.
  const Address& address(const std::string& role, const std::string& program = "");
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

// What a remote transport needs besides the scene.
struct TransportSetup {
  std::map<std::string, Address> given;  // nodes already running, by role
  NodePool* pool = nullptr;              // starts a node for any other role; must outlive runs
  std::optional<std::string> token;      // the shared secret of nodes that require one
  // The most one macro step may take (0: the scene's [coupling] step_budget,
  // else RemoteTimeouts' default).
  std::chrono::milliseconds step_budget{0};
  // The least a macro step is waited for without a word from its node, on
  // both data planes (0: the scene's [coupling] step_deadline_floor, else
  // RemoteTimeouts' step_min).
  std::chrono::milliseconds step_deadline_floor{0};
};

// A transport: where the participants of a run live and how the master
// reaches them. One class each (transport.cpp), named in its table.
class Transport {
 public:
  virtual ~Transport() = default;
  // Its name (transport_names.hpp), as users give it and read it.
  virtual const char* name() const = 0;
  // Whether its participants live in node processes (the data plane applies).
  virtual bool remote() const = 0;
  // Whether it carries couplings with substep waveforms (--inputs waveformK).
  virtual bool carries_waveforms() const = 0;
  // Makes the participants of runs of `scene`.
  virtual ParticipantFactory factory(const Scene& scene, const TransportSetup& setup) const = 0;
};

// The names of the table, in its order (for --transport and study plans).
std::vector<std::string> transport_names();
// The transport of that name, or nullptr.
const Transport* find_transport(const std::string& name);
// The transport of that name; throws std::invalid_argument naming `what`
// (e.g. "--transport") and the names there are.
const Transport& parse_transport(const std::string& name, const std::string& what);
// Whether `name` is a transport whose participants live in node processes.
bool is_remote_transport(const std::string& name);
// A study's stage 2 runs its cheapest methods over the other transport: the
// in-process one for a remote transport, else the first remote one.
std::string other_transport(const std::string& name);
// Throws std::invalid_argument for a coupling the transport does not carry:
// substep waveforms travel in process or relayed over TCP.
void check_transport(const engine::CouplingOptions& o, const std::string& transport);

// A transport made ready for one scene: its name and participant factory.
struct SceneTransport {
  std::string name;
  ParticipantFactory factory;
};

SceneTransport make_transport(const Transport& transport, const Scene& scene,
                              const TransportSetup& setup = {});
SceneTransport inproc_transport(const Scene& scene);
// Over TCP: a participant whose role is in `given` connects there, any other
// to a node of `pool` (which must outlive the transport).
SceneTransport tcp_transport(const Scene& scene, std::map<std::string, Address> given,
                             NodePool& pool, std::optional<std::string> token = std::nullopt);

}  // namespace railcosim::remote
