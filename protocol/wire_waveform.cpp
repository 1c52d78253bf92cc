// Substep waveforms on the wire: the samples a participant records inside a
// macro step (in its StepReport) and the input waveforms a receiver takes (in
// Step or SetInputs). Every number crosses as the double it is, so the
// receiver rebuilds the sender's Waveform bit for bit.
#include <cmath>

#include "wire.hpp"

namespace railcosim {

void to_wire(const OutputSamples& samples, wire::StepReport* report) {
  for (const OutputSample& s : samples) {
    auto* w = report->add_samples();
    w->set_t(s.t);
    *w->mutable_outputs() = to_wire(s.outputs);
  }
}

OutputSamples samples_from_wire(const wire::StepReport& report) {
  OutputSamples out;
  out.reserve(static_cast<std::size_t>(report.samples_size()));
  for (const auto& s : report.samples()) out.push_back({s.t(), from_wire(s.outputs())});
  return out;
}

wire::InputWaveforms to_wire(const InputWaveforms& waveforms) {
  wire::InputWaveforms out;
  for (const Waveform& w : waveforms) {
    auto* o = out.add_interfaces();
    o->set_degree(w.degree());
    o->set_width(static_cast<std::uint32_t>(w.width()));
    for (std::size_t i = 0; i < w.samples(); ++i) {
      o->add_times(w.time(i));
      o->mutable_values()->Add(w.sample(i).begin(), w.sample(i).end());
    }
  }
  return out;
}

InputWaveforms from_wire(const wire::InputWaveforms& waveforms) {
  InputWaveforms out;
  for (int j = 0; j < waveforms.interfaces_size(); ++j) {
    const wire::Waveform& w = waveforms.interfaces(j);
    const std::string where = "waveform of input interface " + std::to_string(j) + ": ";
    if (w.degree() < 0 || w.degree() > Waveform::kMaxDegree)
      throw ProtocolError(wire::Error::BAD_REQUEST,
                          where + "degree " + std::to_string(w.degree()) + " is not 0 to 3");
    const auto width = static_cast<std::size_t>(w.width());
    const auto samples = static_cast<std::size_t>(w.times_size());
    // With one sample or more, the values in the message bound the width
    // (width x samples of them); nothing is allocated for a width before.
    if (samples == 0)
      throw ProtocolError(wire::Error::BAD_REQUEST, where + "no samples (a waveform needs one)");
    if (static_cast<std::size_t>(w.values_size()) != samples * width)
      throw ProtocolError(wire::Error::BAD_REQUEST, where + std::to_string(w.values_size()) +
                                                        " values for " + std::to_string(samples) +
                                                        " samples of " + std::to_string(width));
    Waveform wave(w.degree(), width);
    std::vector<double> v(width);
    for (std::size_t i = 0; i < samples; ++i) {
      const auto at = w.values().begin() + static_cast<std::ptrdiff_t>(i * width);
      v.assign(at, at + static_cast<std::ptrdiff_t>(width));
      bool finite = std::isfinite(w.times(static_cast<int>(i)));
      for (double x : v) finite = finite && std::isfinite(x);
      if (!finite)
        throw ProtocolError(wire::Error::BAD_REQUEST,
                            where + "sample " + std::to_string(i) + " is not finite");
      try {
        wave.add(w.times(static_cast<int>(i)), v);
      } catch (const std::invalid_argument& e) {
        throw ProtocolError(wire::Error::BAD_REQUEST, where + e.what());
      }
    }
    out.push_back(std::move(wave));
  }
  return out;
}

}  // namespace railcosim
