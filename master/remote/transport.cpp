#include "remote/transport.hpp"

#include <cstdlib>

#include "log.hpp"
#include "remote/remote_participant.hpp"

namespace railcosim {

ParticipantFactory inproc_factory(const Scene& scene) {
  return [scene](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    return std::make_unique<Subsystem>(scene, c);
  };
}

std::string node_program(const std::string& role) {
  if (role == "vehicle" || role == "track" || role == "soil") return role + "_node";
  return "track_node";
}

LaunchCommand fe_soil_command(const FeSoilLaunch& fe, const std::string& token_file) {
  const char* override_dir = std::getenv("RAILCOSIM_FE_SOIL");
  const std::string root = override_dir != nullptr && *override_dir != '\0'
                               ? std::string(override_dir)
                               : std::string(RAILCOSIM_SOURCE_DIR);
  LaunchCommand c;
  c.name = "the FE soil (" + root + "/fe_soil/participant.py" +
           (fe.ranks > 1 ? ", " + std::to_string(fe.ranks) + " MPI ranks" : "") + ")";
  if (fe.ranks > 1) c.argv = {"/usr/bin/mpirun", "-n", std::to_string(fe.ranks)};
  c.argv.insert(c.argv.end(),
                {"/usr/bin/python3", "-m", "fe_soil.participant", "--listen", "127.0.0.1:0"});
  if (!fe.output_dir.empty()) c.argv.insert(c.argv.end(), {"--output-dir", fe.output_dir});
  if (!token_file.empty()) c.argv.insert(c.argv.end(), {"--token-file", token_file});
  const char* path = std::getenv("PYTHONPATH");
  c.env = {"PYTHONPATH=" + root + (path != nullptr && *path != '\0' ? ":" + std::string(path) : ""),
           // One thread per rank: the other participants share the cores.
           "OMP_NUM_THREADS=1", "OPENBLAS_NUM_THREADS=1",
           // Open MPI refuses root without these, and more ranks than cores
           // without the last.
           "OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
           "OMPI_MCA_rmaps_base_oversubscribe=1",
           // Ranks waiting for each other yield the core (the master and the
           // other participants run beside them).
           "OMPI_MCA_mpi_yield_when_idle=1"};
  return c;
}

const Address& NodePool::address(const std::string& role) {
  auto it = nodes_.find(role);
  if (it == nodes_.end() && role == "soil" && fe_) {
    auto node = std::make_unique<LaunchedNode>(fe_soil_command(*fe_, token_file_), kFeSoilStart);
    logger("master")->info("started the FE soil ({} rank{}) on {}", fe_->ranks,
                           fe_->ranks > 1 ? "s" : "", node->address().str());
    it = nodes_.emplace(role, std::move(node)).first;
  }
  if (it == nodes_.end()) {
    const std::string program = node_program(role);
    std::vector<std::string> extra;
    if (fe_) extra = {"--idle-timeout", std::to_string(kIdleBesideFeSoil.count())};
    auto node =
        std::make_unique<LaunchedNode>(program, std::chrono::seconds(10), "127.0.0.1:0",
                                       program == role + "_node" ? "" : role, token_file_, extra);
    logger("master")->info("started {} for the {} participant on {}", program, role,
                           node->address().str());
    it = nodes_.emplace(role, std::move(node)).first;
  }
  return it->second->address();
}

Transport inproc_transport(const Scene& scene) {
  return {"inproc", inproc_factory(scene)};
}

Transport tcp_transport(const Scene& scene, std::map<std::string, Address> given, NodePool& pool,
                        std::optional<std::string> token) {
  Transport t;
  t.name = "tcp";
  t.factory = [scene, given = std::move(given), &pool,
               token](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    const auto it = given.find(c.participant.role);
    const Address address = it != given.end() ? it->second : pool.address(c.participant.role);
    RemoteTimeouts timeouts;
    if (scene.soil_model == "fe" && c.participant.parts.has(Component::kSoil))
      timeouts.reply = kFeSoilReply;  // a mesh to build, a static solver to set up
    return std::make_unique<RemoteParticipant>(address, scene, c, timeouts, token);
  };
  return t;
}

}  // namespace railcosim
