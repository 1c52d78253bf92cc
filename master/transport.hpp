// Where the participants of a co-simulation live: in the master, or on
// nodes, either already running where the user says or started here on
// loopback, one per participant role.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "connection.hpp"
#include "node_launcher.hpp"
#include "runner.hpp"

namespace railcosim {

// The node program that serves a role by default ("vehicle" -> vehicle_node;
// the rail alone is served by track_node --role rail).
std::string node_program(const std::string& role);

// Nodes started on loopback on demand, one per role, kept for the runs that
// follow (each node serves its sessions one after another).
class NodePool {
 public:
  // With a `token_file`, the nodes it starts require that shared secret.
  explicit NodePool(std::string token_file = "") : token_file_(std::move(token_file)) {}
  const Address& address(const std::string& role);

 private:
  std::string token_file_;
  std::map<std::string, std::unique_ptr<LaunchedNode>> nodes_;
};

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
