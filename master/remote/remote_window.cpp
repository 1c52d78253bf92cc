// The direct data plane's side of a node's proxy: the lock step, the peer
// links, the windows it grants and the reports and the end that answer them,
// each checked before it counts.
#include <sstream>

#include "remote/peer_text.hpp"
#include "remote/remote_participant.hpp"
#include "wire.hpp"

namespace railcosim::remote {

void RemoteParticipant::enter_lockstep(long first_step, long end_step) {
  wire::Envelope e;
  auto* w = e.mutable_window();
  w->set_first_step(first_step);
  w->set_end_step(end_step);
  w->set_lockstep(true);
  send(e, true);  // its ack is read with the next reply
  lockstep_ = true;
  stepping_ = true;
}

void RemoteParticipant::set_links(const wire::Links& links) {
  wire::Envelope e;
  *e.mutable_links() = links;
  send(e, true);
  await(wire::Envelope::kAck, "links");
}

void RemoteParticipant::grant(const wire::Window& window) {
  step_ = static_cast<long>(window.first_step());
  window_end_ = static_cast<long>(window.end_step());
  stepping_ = true;
  wire::Envelope e;
  *e.mutable_window() = window;
  send(e, false);
}

void RemoteParticipant::accept_reports_frame(std::uint64_t id) const {
  // Report frames belong to the window granted: they carry its id.
  check(check_reply_id(id, in_flight_.empty() ? 0 : in_flight_.front()));
}

StepResult RemoteParticipant::accept_report(const wire::StepReport& w) {
  if (static_cast<long>(w.step()) > window_end_)
    fail("bad reply: a step report for macro step " + std::to_string(w.step()) +
         ", past the end of the window granted (macro step " + std::to_string(window_end_) + ")");
  StepResult r = from_wire(w);
  check(check_step_report(r, w.step(), w.t(), step_ + 1, shape_));
  step_ = static_cast<long>(w.step());
  return r;
}

void RemoteParticipant::window_reply(const wire::Envelope& reply) {
  if (!reply.has_error())
    check(check_reply_id(reply.id(), in_flight_.empty() ? 0 : in_flight_.front()));
  if (!in_flight_.empty()) in_flight_.pop_front();
  if (reply.has_error()) {
    const auto& err = reply.error();
    if (err.step() >= 0) step_ = static_cast<long>(err.step());
    if (err.code() == wire::Error::STEP_FAILED) {
      std::ostringstream s;
      s << name() << ": " << terminal_text(err.message()) << " at macro step " << step_;
      throw StepFailure(s.str());
    }
    fail("window failed: " + wire::Error::Code_Name(err.code()) + ": " +
         terminal_text(err.message()));
  }
  if (!reply.has_window_done()) fail("unexpected " + body_name(reply) + " in reply to window");
  // Its step reports came before it on the same stream: the window ended
  // where they did.
  if (static_cast<long>(reply.window_done().step()) != step_)
    fail("its window ended at macro step " + std::to_string(reply.window_done().step()) +
         ", but its step reports stop at macro step " + std::to_string(step_));
}

}  // namespace railcosim::remote
