// The parked co-simulation both stability measures start from (the dense
// map, spectral.cpp; the matrix-free rate, matrix_free.cpp): a case's
// participants, made by a factory, brought from their coupled static state
// through two macro steps (so that extrapolated inputs have their past
// points) and saved there: their snapshots and the master's memory.
#pragma once

#include <memory>
#include <vector>

#include "cosim_case.hpp"
#include "engine/schedule.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"

namespace railcosim::run {

struct ParkedParticipants {
  static constexpr long kStart = 2;  // the macro steps taken before the save

  ParkedParticipants(const Scene& parked, const CaseSpec& spec, const RunOptions& o,
                     const remote::ParticipantFactory& make);

  std::vector<std::unique_ptr<Participant>> owned;
  std::vector<Participant*> ps;
  std::unique_ptr<engine::Schedule> schedule;
  std::vector<ParticipantState> saved;  // each participant at rest
  engine::StepExecutor::Memory rest;    // the master's memory at rest
};

}  // namespace railcosim::run
