// The requests of a configured session, one handler each (the dispatch and
// the handlers before configure are in session.cpp).
#include "session.hpp"

namespace railcosim {
namespace {

wire::Envelope reply_to(const wire::Envelope& req) {
  wire::Envelope reply;
  reply.set_id(req.id());
  return reply;
}

}  // namespace

wire::Envelope NodeSession::on_statics(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  auto* o = reply.mutable_outputs();
  *o->mutable_data() = to_wire(served_->statics(from_wire(req.statics().inputs())));
  o->set_step(0);
  o->set_t(0.0);
  return reply;
}

wire::Envelope NodeSession::on_initialize(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  const StepResult r = served_->initialize(from_wire(req.initialize().inputs()));
  step_ = 0;
  outputs_ = r.outputs;
  *reply.mutable_step_report() = to_wire(r, 0, 0.0);
  return reply;
}

wire::Envelope NodeSession::on_set_inputs(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  const auto& s = req.set_inputs();
  if (s.has_waveforms())
    take_waveforms(static_cast<long>(s.step()), s.waveforms(), s.has_inputs());
  else if (s.has_inputs_end())
    served_->set_inputs(static_cast<long>(s.step()), from_wire(s.inputs()),
                        from_wire(s.inputs_end()));
  else
    served_->set_inputs(static_cast<long>(s.step()), from_wire(s.inputs()));
  reply.mutable_ack();
  return reply;
}

wire::Envelope NodeSession::on_get_outputs(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  auto* o = reply.mutable_outputs();
  *o->mutable_data() = to_wire(served_->outputs());
  o->set_step(step_);
  o->set_t(static_cast<double>(step_) * macro_step_);
  return reply;
}

wire::Envelope NodeSession::on_step(const wire::Envelope& req) {
  Participant& sub = *served_;
  const auto& s = req.step();
  if (s.h() != macro_step_)
    throw ProtocolError(
        wire::Error::BAD_REQUEST,
        "step " + std::to_string(s.step()) + " asks for h = " + std::to_string(s.h()) +
            " s, but the session was configured with H = " + std::to_string(macro_step_) + " s");
  const long n = static_cast<long>(s.step());
  if (s.has_inputs_end() && !s.has_inputs())
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        "step " + std::to_string(n) + " carries inputs_end without inputs");
  if (s.keep_checkpoint()) kept_ = sub.save();
  if (s.restore_checkpoint()) restore_kept(sub);
  if (s.has_waveforms())
    take_waveforms(n, s.waveforms(), s.has_inputs());
  else if (s.has_inputs_end())
    sub.set_inputs(n, from_wire(s.inputs()), from_wire(s.inputs_end()));
  else if (s.has_inputs())
    sub.set_inputs(n, from_wire(s.inputs()));
  const StepResult r = sub.step(n);
  step_ = n + 1;
  wire::Envelope reply = reply_to(req);
  *reply.mutable_step_report() = to_wire(r, step_, static_cast<double>(step_) * macro_step_);
  if (record_) to_wire(sub.step_samples(), reply.mutable_step_report());
  return reply;
}

wire::Envelope NodeSession::on_get_results(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  const ParticipantResults r = served_->results();
  auto* w = reply.mutable_results();
  for (const auto& f : r.fields) w->add_fields()->mutable_values()->Add(f.begin(), f.end());
  w->set_micro_steps(r.micro_steps);
  return reply;
}

wire::Envelope NodeSession::on_save(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  if (req.save().keep()) {
    kept_ = served_->save();
    reply.mutable_ack();
    return reply;
  }
  const ParticipantState st = served_->save();
  auto* w = reply.mutable_state();
  for (double v : st.values) w->add_values(v);
  return reply;
}

wire::Envelope NodeSession::on_restore(const wire::Envelope& req) {
  wire::Envelope reply = reply_to(req);
  if (req.restore().kept()) {
    restore_kept(*served_);
    reply.mutable_ack();
    return reply;
  }
  const auto& values = req.restore().state().values();
  served_->restore(ParticipantState{{values.begin(), values.end()}});
  reply.mutable_ack();
  return reply;
}

void NodeSession::watch_progress(std::optional<ScopedWorkProgress>& scope, std::uint64_t id,
                                 std::function<long()> step) {
  if (!report_ || progress_every_.count() == 0) return;
  scope.emplace(
      [this, id, step = std::move(step)](std::uint64_t done) {
        wire::Envelope e;
        e.set_id(id);
        auto* p = e.mutable_progress();
        p->set_step(step());
        p->set_micro_steps(done);
        report_(encode_frame(e));
      },
      progress_every_);
}

}  // namespace railcosim
