#include "transport.hpp"

#include "log.hpp"
#include "remote_participant.hpp"

namespace railcosim {

std::string node_program(const std::string& role) {
  if (role == "vehicle" || role == "track" || role == "soil") return role + "_node";
  return "track_node";
}

const Address& NodePool::address(const std::string& role) {
  auto it = nodes_.find(role);
  if (it == nodes_.end()) {
    const std::string program = node_program(role);
    auto node = std::make_unique<LaunchedNode>(program, std::chrono::seconds(10), "127.0.0.1:0",
                                               program == role + "_node" ? "" : role, token_file_);
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
    return std::make_unique<RemoteParticipant>(address, scene, c, RemoteTimeouts{}, token);
  };
  return t;
}

}  // namespace railcosim
