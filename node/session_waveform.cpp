// Substep waveforms in a node's session: RecordSamples turns the served
// participant's recording on or off, and a Step or SetInputs may carry the
// step's inputs as waveforms. A participant that takes neither refuses with
// an error that names it and the option to change.
#include <sstream>

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
  check_waveforms(n, waveforms);
  const InputWaveforms w = from_wire(waveforms);
  try {
    served_->set_input_waveforms(n, w);
  } catch (const CallOrderError& e) {
    const std::string what = e.what();
    if (what.find("takes no substep waveforms") == std::string::npos) throw;
    refuse(participant_, what);
  }
}

void NodeSession::check_waveforms(long n, const wire::InputWaveforms& waveforms) const {
  const std::string at = "macro step " + std::to_string(n) + ": ";
  auto bad = [&](const std::string& why) {
    return ProtocolError(wire::Error::BAD_REQUEST, at + why);
  };
  if (static_cast<std::size_t>(waveforms.interfaces_size()) != in_shape_.size())
    throw bad("waveforms for " + std::to_string(waveforms.interfaces_size()) +
              " interfaces; participant " + participant_ + " has " +
              std::to_string(in_shape_.size()));
  // A sample's time may stray from the window by a thousandth of a step.
  const double slack = 1e-3 * macro_step_;
  const double t0 = static_cast<double>(n) * macro_step_;
  const double t1 = static_cast<double>(n + 1) * macro_step_;
  for (std::size_t j = 0; j < in_shape_.size(); ++j) {
    const wire::Waveform& w = waveforms.interfaces(static_cast<int>(j));
    const std::size_t width = in_shape_[j][0] + in_shape_[j][1] + in_shape_[j][2];
    const std::string of = "the waveform of input interface " + std::to_string(j);
    if (w.width() != width)
      throw bad(of + " has width " + std::to_string(w.width()) + "; participant " + participant_ +
                " takes " + std::to_string(width) + " values there");
    if (w.times_size() == 0 || static_cast<std::size_t>(w.times_size()) > max_samples_)
      throw bad(of + " has " + std::to_string(w.times_size()) + " samples; 1 to " +
                std::to_string(max_samples_) + " are allowed (one per micro step and one more)");
    for (int i = 0; i < w.times_size(); ++i)
      if (!(w.times(i) >= t0 - slack && w.times(i) <= t1 + slack)) {
        std::ostringstream m;
        m.precision(10);
        m << of << ": sample " << i << " at t = " << w.times(i)
          << " s lies outside the macro step [" << t0 << ", " << t1 << "] s (tolerance " << slack
          << " s)";
        throw bad(m.str());
      }
  }
}

}  // namespace railcosim
