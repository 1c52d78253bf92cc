// A participant that lives in a node process: the master's proxy for it.
// Every call becomes a message to the node; the schedules cannot tell it
// from an in-process Subsystem.
#pragma once

#include <chrono>
#include <memory>
#include <optional>

#include "connection.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim {

struct RemoteTimeouts {
  std::chrono::milliseconds connect{10000};  // a node may still be starting
  std::chrono::milliseconds reply{60000};    // any reply, a step included
};

// A failure of a remote node, with its name, address, macro step and time.
class NodeFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RemoteParticipant final : public Participant {
 public:
  // Connects, says hello (checking the node's role and the scene) and
  // configures the node's subsystem. Throws NodeFailure.
  RemoteParticipant(const Address& address, const Scene& scene, const SubsystemConfig& config,
                    RemoteTimeouts timeouts = {});
  ~RemoteParticipant() override;

  std::string name() const override;
  StepResult initialize() override;
  void set_inputs(long n, const CouplingData& inputs) override;
  CouplingData outputs() override;
  void start_step(long n) override;
  StepResult finish_step() override;
  ParticipantResults results() override;
  ParticipantState save() override;
  void restore(const ParticipantState& state) override;

 private:
  // Sends a request; replies are read later, in order.
  void send(wire::Envelope request, bool expects_ack);
  // Reads replies until the one for the latest non-ack request; acks of
  // pipelined requests are consumed on the way.
  wire::Envelope await(wire::Envelope::BodyCase expected, const char* what);
  [[noreturn]] void fail(const std::string& what) const;
  // Sends inputs held back by set_inputs() as a message of their own.
  void flush_inputs();

  Address address_;
  SubsystemConfig config_;
  RemoteTimeouts timeouts_;
  std::unique_ptr<Connection> conn_;
  std::uint64_t next_id_ = 1;
  int pending_acks_ = 0;
  long step_ = 0;  // the macro step being done, for messages
  // set_inputs() keeps its data here; the next step carries it.
  std::optional<CouplingData> pending_inputs_;
};

}  // namespace railcosim
