// The parked co-simulation both stability measures start from (the dense
// map, spectral.cpp; the matrix-free rate, matrix_free.cpp): a case's
// participants, made by a factory, brought from their coupled static state
// through two steps of the coupled map (so that extrapolated inputs have
// their past points; a multirate plan's steps are its slow windows) and saved
// there: their snapshots and the master's memory.
#pragma once

#include <memory>
#include <vector>

#include "cosim_case.hpp"
#include "engine/multirate.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"

namespace railcosim::run {

struct ParkedParticipants {
  static constexpr long kStart = 2;  // the macro steps taken before the save

  ParkedParticipants(const Scene& parked, const CaseSpec& spec, const RunOptions& o,
                     const remote::ParticipantFactory& make);

  std::vector<std::unique_ptr<Participant>> owned;
  std::vector<Participant*> ps;
  engine::RatePlan rates;
  std::unique_ptr<engine::CoupledSteps> schedule;  // one rate or two; a map step spans
                                                   // schedule->map_windows() finest windows
  std::vector<ParticipantState> saved;             // each participant at rest
  engine::CoupledSteps::Memory rest;               // the master's memory at rest
};

}  // namespace railcosim::run
