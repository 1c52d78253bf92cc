// The record a run makes and fills as it goes, which the verdict judges
// (verdict/run_record.hpp): the run module's name for it.
#pragma once

#include "verdict/run_record.hpp"

namespace railcosim::run {

using RunRecord = verdict::RunRecord;

}  // namespace railcosim::run
