// The frames a macro step sends and receives, as the master and the nodes
// encode them: the sizes a benchmark's raw socket baseline carries.
#pragma once

#include <algorithm>
#include <utility>

#include "coupled_statics.hpp"
#include "runner.hpp"
#include "scene.hpp"
#include "transport.hpp"
#include "wire.hpp"

namespace railcosim {

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
    const CouplingData inputs = zero_inputs(scene, p);
    const StepResult r = inproc_factory(scene)(cfg)->initialize(inputs);
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

}  // namespace railcosim
