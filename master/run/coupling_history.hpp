// What a run records of its coupling as it goes, for the verdict to judge
// (verdict/evaluation.hpp: coupling_history_error; verdict/stability.hpp:
// deviation_from_rest, coupling_defect): per linear cut ("rs", "ss") the
// largest displacement of its lower side over the coupling points, one
// value per history row (RunRecord::coupling_history).
#pragma once

#include <vector>

#include "model.hpp"
#include "monolithic.hpp"
#include "participant.hpp"
#include "run/run_record.hpp"

namespace railcosim::run {

// Appends one row of RunRecord::coupling_history: from the outputs of a
// co-simulation's participants, or from the monolithic model's state.
void record_coupling(RunRecord& run, const std::vector<ParticipantSpec>& participants,
                     const std::vector<StepResult>& outputs);
void record_coupling(RunRecord& run, const MonolithicModel& model);

}  // namespace railcosim::run
