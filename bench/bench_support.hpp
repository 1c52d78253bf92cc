// What the network benchmarks share: the frames a macro step sends and
// receives, as the master and the nodes encode them (the sizes the raw
// socket baseline carries), the baseline itself, and the check of a run.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

#include "raw_pingpong.hpp"

#include "engine/coupled_statics.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene.hpp"
#include "wire.hpp"

namespace railcosim {

// The network benchmarks' common ground: the paper's macro step, and the
// raw socket baseline every overhead is divided by (measured in the same
// run): the lowest of kRawForks medians of kRawSamples round trips.
inline constexpr double kMacroStep = 1e-4;  // H, s
inline constexpr int kRawSamples = 2000;    // round trips per raw measurement
inline constexpr int kRawForks = 3;         // raw measurements per repeat

// The largest Step request and StepReport frame of a macro step of the case
// (the inputs and outputs of the participants at t = 0, which have their
// sizes all run long). `ramped`: the step carries the inputs at the step's
// end too (inputs_end), as ramped inputs and implicit iterations do.
inline std::pair<std::size_t, std::size_t> step_frame_bytes(const Scene& scene,
                                                            const CaseSpec& spec, double H,
                                                            bool ramped = false) {
  std::size_t request = 0, reply = 0;
  for (const ParticipantSpec& p : partition(scene, spec)) {
    SubsystemConfig cfg;
    cfg.participant = p;
    cfg.macro_step = H;
    cfg.tolerance = scene.tolerance;
    const CouplingData inputs = engine::zero_inputs(scene, p);
    const StepResult r = remote::inproc_factory(scene)(cfg)->initialize(inputs);
    wire::Envelope step;
    step.set_id(12345);
    step.mutable_step()->set_step(1234);
    step.mutable_step()->set_t(0.1234);
    step.mutable_step()->set_h(H);
    *step.mutable_step()->mutable_inputs() = to_wire(inputs);
    if (ramped) *step.mutable_step()->mutable_inputs_end() = to_wire(inputs);
    wire::Envelope report;
    report.set_id(12345);
    *report.mutable_step_report() = to_wire(r, 1235, 0.1235);
    request = std::max(request, encode_frame(step).size());
    reply = std::max(reply, encode_frame(report).size());
  }
  return {request, reply};
}

// The lowest median of `forks` raw measurements of `samples` round trips,
// each with a new child: the fastest plain sockets go, never one the
// product beats by luck of placement.
inline RawRoundTrip lowest_raw_round_trip(std::size_t request, std::size_t reply, int samples,
                                          int forks) {
  RawRoundTrip raw;
  raw.median_us = 1e30;
  for (int f = 0; f < forks; ++f) {
    const RawRoundTrip r = raw_round_trip(request, reply, samples);
    if (r.median_us < raw.median_us) raw = r;
  }
  return raw;
}

// The baseline of a repeat with these frame sizes (kRawForks x kRawSamples).
inline RawRoundTrip raw_baseline(std::size_t request, std::size_t reply) {
  return lowest_raw_round_trip(request, reply, kRawSamples, kRawForks);
}

// Exits with status 1, naming `program` and the case, when a run failed or
// did not take the data plane asked for.
inline void require_ran(const char* program, const run::RunRecord& r, const CaseSpec& spec,
                        const std::string& transport, remote::DataPlane plane) {
  if (r.status == "failed" || r.macro_steps == 0) {
    std::fprintf(stderr, "%s: %s failed: %s\n", program, spec.name().c_str(), r.message.c_str());
    std::exit(1);
  }
  if (transport == "tcp" && r.data_plane != to_string(plane)) {
    std::fprintf(stderr, "%s: %s ran on the %s data plane, not the %s one\n", program,
                 spec.name().c_str(), r.data_plane.c_str(), to_string(plane).c_str());
    std::exit(1);
  }
}

}  // namespace railcosim
