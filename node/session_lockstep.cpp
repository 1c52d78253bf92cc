// The lock step of a session: the master decides every macro step
// (implicit coupling, ramped inputs) but the node serves its step requests
// on the thread that runs the window, reading and writing the master's
// socket itself, without the event loop's hand-overs between threads. Each
// request is handled by the same dispatch as on the relayed plane, so the
// results are bitwise the same.
#include <chrono>

#include "session.hpp"
#include "work_budget.hpp"

namespace railcosim {
namespace {

// The requests a lock step serves; any other ends it.
bool step_request(const wire::Envelope& e) {
  using E = wire::Envelope;
  switch (e.body_case()) {
    case E::kSetInputs:
    case E::kGetOutputs:
    case E::kStep:
    case E::kSave:
    case E::kRestore:
    case E::kRecordSamples:
      return true;
    default:
      return false;
  }
}

}  // namespace

void NodeSession::restore_kept(Participant& participant) {
  if (!kept_)
    throw ProtocolError(wire::Error::OUT_OF_ORDER,
                        "restore of the kept checkpoint, but none was kept (a save with keep, or "
                        "a step with keep_checkpoint, comes first)");
  participant.restore(*kept_);
}

wire::Envelope NodeSession::lockstep(const wire::Envelope& req, bool& close) {
  auto refuse = [&](wire::Error::Code code, const std::string& why) {
    close = true;
    return error_envelope(req.id(), code, why, step_,
                          step_ < 0 ? 0.0 : static_cast<double>(step_) * macro_step_);
  };
  if (step_ < 0) return refuse(wire::Error::OUT_OF_ORDER, "a lock step needs initialize first");
  if (runner_)
    return refuse(wire::Error::OUT_OF_ORDER,
                  "a lock step cannot follow windows of the direct data plane in one session");
  if (!report_ || !next_request_)
    return refuse(wire::Error::BAD_REQUEST, "this connection cannot serve a lock step");
  const long first = step_;
  auto refuse_nested = [&](const wire::Envelope& next) {
    close = true;
    return error_envelope(next.id(), wire::Error::OUT_OF_ORDER,
                          "a lock-step Window inside the lock step entered at macro step " +
                              std::to_string(first) +
                              ": a session enters one lock step, which ends with a request "
                              "of another kind",
                          step_, static_cast<double>(step_) * macro_step_);
  };
  WorkBudget& budget = current_work_budget();
  wire::Envelope reply;
  reply.set_id(req.id());
  reply.mutable_ack();
  try {
    while (true) {
      report_(encode_frame(reply, max_frame_bytes_));
      wire::Envelope next;
      if (!next_request_(next))
        return refuse(wire::Error::INTERNAL,
                      "the master closed its connection during the lock step at macro step " +
                          std::to_string(step_));
      // A lock step is entered once: a second one inside it is refused, not
      // served by a nested loop (one stack frame per window until the stack
      // ran out).
      if (next.has_window() && next.window().lockstep()) return refuse_nested(next);
      if (!step_request(next)) return handle(next, close);
      // Each request has the whole budget of a macro step's work.
      if (budget.limit.count() > 0)
        budget.deadline = std::chrono::steady_clock::now() + budget.limit;
      reply = handle(next, close);
      if (close) return reply;  // an error: it ends the session
    }
  } catch (const ProtocolError& e) {
    return refuse(e.code(), e.what());
  } catch (const LinkError& e) {
    // The master does not read what it is sent.
    return refuse(wire::Error::TIMEOUT, e.what());
  }
}

}  // namespace railcosim
