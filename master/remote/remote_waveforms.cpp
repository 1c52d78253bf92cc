// Substep waveforms over the relayed data plane: the master's proxy turns
// recording on with RecordSamples, keeps the samples of each step report,
// and sends input waveforms along with the next Step (or in a SetInputs
// before any other request), as it does held inputs.
#include <cmath>
#include <sstream>

#include "remote/remote_participant.hpp"
#include "wire.hpp"

namespace railcosim::remote {

void RemoteParticipant::set_input_waveforms(long n, const InputWaveforms& inputs) {
  step_ = n;
  stepping_ = true;
  pending_waves_ = inputs;
  pending_inputs_.reset();
  pending_end_.reset();
}

void RemoteParticipant::record_samples(bool on) {
  wire::Envelope e;
  e.mutable_record_samples()->set_on(on);
  flush_inputs();
  send(e, true);
  await(wire::Envelope::kAck, "record_samples");
  record_ = on;
  samples_.clear();
}

void RemoteParticipant::keep_samples(const wire::StepReport& report) {
  if (!record_) {
    if (report.samples_size() > 0) fail("bad reply: step report carries samples unasked");
    return;
  }
  OutputSamples s = samples_from_wire(report);
  if (s.empty()) fail("bad reply: step report carries no samples while recording is on");
  // The samples of macro step step_ lie in its window, give or take a
  // thousandth of a step (as the report's own time).
  const double H = config_.macro_step, slack = 1e-3 * H;
  const double t0 = static_cast<double>(step_) * H, t1 = static_cast<double>(step_ + 1) * H;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!std::isfinite(s[i].t) || (i > 0 && !(s[i].t > s[i - 1].t)))
      fail("bad reply: sample " + std::to_string(i) + " of the step report at t = " +
           std::to_string(s[i].t) + " s: times must be finite and increase");
    if (!(s[i].t >= t0 - slack && s[i].t <= t1 + slack)) {
      std::ostringstream m;
      m.precision(10);
      m << "bad reply: sample " << i << " of the step report at t = " << s[i].t
        << " s lies outside the step's window [" << t0 << ", " << t1 << "] s (tolerance " << slack
        << " s)";
      fail(m.str());
    }
    const std::string why = check_outputs(s[i].outputs, shape_);
    if (!why.empty()) fail("bad reply: sample " + std::to_string(i) + ": " + why);
  }
  samples_ = std::move(s);
}

}  // namespace railcosim::remote
