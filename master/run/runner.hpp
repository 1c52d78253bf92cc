// Runs one case from start to finish: the monolithic reference, or a
// co-simulation driven by a schedule over two participants.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "cosim_case.hpp"
#include "engine/coupling_options.hpp"
#include "engine/rate_plan.hpp"
#include "participant.hpp"
#include "remote/data_plane.hpp"
#include "remote/transport.hpp"
#include "run/run_record.hpp"
#include "scene.hpp"
#include "subsystem.hpp"
#include "verdict/judge_options.hpp"

namespace railcosim::run {

// What the verdict measures after the run (verdict/judge_options.hpp).
using verdict::JudgeMode;
using verdict::JudgeOptions;

struct RunOptions {
  double macro_step = 0;  // H, s
  double tolerance = 0;   // micro-step local error bound, m
  // Multirate: a cut's window in finest windows H, by the cut's name ("ss");
  // a cut not named exchanges every H.
  std::map<std::string, long> cut_windows;
  Feedthrough feedthrough = Feedthrough::kLagged;
  engine::CouplingOptions coupling;  // explicit with held inputs unless asked otherwise
  // Over TCP: the nodes exchange directly in windows of macro steps where every
  // node can and the coupling is explicit with held inputs; otherwise relayed.
  remote::DataPlane data_plane = remote::DataPlane::kDirect;
  remote::DirectOptions direct;  // windows and reports of the direct data plane
  // Called with every history row as soon as it is known (t = 0 first), so
  // that the history reaches the disk while the run goes on.
  std::function<void(const HistoryRow&)> on_row;
  // Called once, before the first row, with the names of HistoryRow::extra.
  std::function<void(const std::vector<std::string>&)> on_channels;
  // When set and non-zero (a signal number), the run stops at the next macro
  // step with an error saying so.
  const std::atomic<int>* stop = nullptr;
  // Called after every macro step with the steps done and the total.
  std::function<void(long done, long total)> on_progress;
  JudgeOptions judge;
};

// The rates of a co-simulation case under these options (single-rate when
// no cut has a window of its own). Throws std::invalid_argument when the
// windows cannot be coupled (engine/rate_plan.hpp: plan_rates()).
engine::RatePlan rate_plan(const Scene& scene, const CaseSpec& spec, const RunOptions& options);
// The macro step the participant of `role` takes in this case: H times its
// window (multirate), H when single-rate or when the case has no such role.
double participant_step(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                        const std::string& role);
// Throws std::invalid_argument when the scene's end time is not a whole
// number of the plan's slow window.
void check_whole_windows(const Scene& scene, const RunOptions& options,
                         const engine::RatePlan& rates);

// The record of a run that could not finish: status "failed" and why.
RunRecord failed_record(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                        const std::string& transport, const std::string& why);

// The monolithic model from the static state to t_end; history every H.
RunRecord run_monolithic(const Scene& scene, const RunOptions& options);

// A co-simulation case. A divergence ends the run early with status
// "diverged" and a message naming the macro step and time; errors and the
// amplification check are left to judge().
RunRecord run_cosim(const Scene& scene, const CaseSpec& spec, const RunOptions& options,
                    const remote::ParticipantFactory& make, const std::string& transport);

}  // namespace railcosim::run
