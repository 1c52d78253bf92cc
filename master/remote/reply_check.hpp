// What the master checks in every reply of a node before it stores or
// computes with anything in it: the reply's id, the macro step and time a
// step report names, the number and sizes of the interfaces and values,
// finiteness, the declared history channels and result fields, and the
// micro-step count. A node is a peer, not a part of the master: a reply that
// does not fit what was asked fails the run, naming that node.
//
// Every check returns an empty string when the reply is fine, otherwise what
// is wrong with it (the caller adds the node, its address and the macro step).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim::remote {

// What the replies of one participant must look like.
struct ReplyShape {
  struct Interface {
    std::string cut;              // "wr", "rs", "ss"
    std::size_t points = 0;       // coupling points
    std::vector<Quantity> sends;  // the quantities it sends there (the others stay empty)
  };
  std::vector<Interface> interfaces;
  double macro_step = 0;
  std::size_t history = 0;  // declared history channels
  // Declared result fields and the size each must have (0: any size).
  std::vector<std::string> results;
  std::vector<std::size_t> result_sizes;
  std::size_t rail_nodes = 0, sleepers = 0;
};

// The shape of a participant's replies before configure.
ReplyShape reply_shape(const Scene& scene, const SubsystemConfig& config);
// Adds what the node declared in reply to configure; returns what is wrong
// with the declaration (a channel twice, a known field of no use, ...).
std::string declare_channels(ReplyShape& shape, const Channels& declared);
// Throws std::runtime_error, naming the participant and the name, unless
// every name the participants declare is acceptable and declared once in the
// run (channel_names.hpp): a second `wheel_m` would overwrite the vehicle's.
void require_distinct_channels(const std::vector<Participant*>& ps);

// The id of a reply against that of the request it answers.
std::string check_reply_id(std::uint64_t got, std::uint64_t want);
// Outputs (of statics, get_outputs or a step): one entry per interface, each
// sent quantity one finite value per coupling point, the others empty.
std::string check_outputs(const CouplingData& outputs, const ReplyShape& shape);
// A step report (or initialize's, want_step 0): the communication point it
// names, its time (within kTimeSlack macro steps of step * H), its outputs,
// its history values and maximum displacement. A report that says its state
// is not finite may carry non-finite values: the run then diverges.
std::string check_step_report(const StepResult& report, std::int64_t got_step, double got_t,
                              std::int64_t want_step, const ReplyShape& shape);
// Final results: one field per declared result, each of its size, finite,
// and a micro-step count >= 0.
std::string check_results(const ParticipantResults& results, const ReplyShape& shape);
// A saved state: finite values only.
std::string check_state(const ParticipantState& state);

// A step report's time may differ from step * H by this many macro steps: an
// outside participant may add H up step by step (after 10^6 steps the sum is
// off by about 10^-4 H), but not name another communication point.
inline constexpr double kTimeSlack = 1e-3;

}  // namespace railcosim::remote
