// What an implicit run's iterations did: the residual of every coupled
// quantity per iteration and macro step.
#pragma once

#include <string>
#include <vector>

namespace railcosim::engine {

struct ConvergenceRow {
  long step = 0;                 // macro step n: the window [nH, (n+1)H]
  int iteration = 0;             // 1, 2, ...
  std::vector<double> residual;  // relative residual per quantity (window_schedule.hpp)
};

struct ConvergenceLog {
  std::vector<std::string> quantities;  // e.g. "track_to_vehicle_displacement"
  using Row = ConvergenceRow;
  std::vector<Row> rows;
  std::vector<int> iterations;  // per macro step
  long not_converged = 0;       // macro steps that hit the iteration limit
  long first_not_converged = -1;
};

}  // namespace railcosim::engine
