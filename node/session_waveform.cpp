// Substep waveforms in a node's session: RecordSamples turns the served
// participant's recording on or off, and a Step or SetInputs may carry the
// step's inputs as waveforms. A participant that takes neither refuses with
// an error that names it and the option to change.
#include "session.hpp"

namespace railcosim {
namespace {

[[noreturn]] void refuse(const std::string& participant, const std::string& why) {
  throw ProtocolError(wire::Error::BAD_REQUEST,
                      "participant " + participant + " takes no substep waveforms (" + why +
                          "): run it with --inputs hold or linear, not waveform0 to waveform3");
}

}  // namespace

wire::Envelope NodeSession::record_samples(const wire::Envelope& req) {
  if (step_ < 0) throw ProtocolError(wire::Error::OUT_OF_ORDER, "record_samples before initialize");
  const bool on = req.record_samples().on();
  try {
    served_->record_samples(on);
  } catch (const CallOrderError& e) {
    refuse(participant_, e.what());
  }
  record_ = on;
  wire::Envelope reply;
  reply.set_id(req.id());
  reply.mutable_ack();
  return reply;
}

void NodeSession::take_waveforms(long n, const wire::InputWaveforms& waveforms, bool with_inputs) {
  if (with_inputs)
    throw ProtocolError(wire::Error::BAD_REQUEST,
                        "macro step " + std::to_string(n) +
                            ": inputs and waveforms in one message; send one of them");
  const InputWaveforms w = from_wire(waveforms);
  try {
    served_->set_input_waveforms(n, w);
  } catch (const CallOrderError& e) {
    const std::string what = e.what();
    if (what.find("takes no substep waveforms") == std::string::npos) throw;
    refuse(participant_, what);
  }
}

}  // namespace railcosim
