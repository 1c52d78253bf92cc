// Writes a run's files in DIR/CASE/: deflection.csv, history.csv and
// summary.json. Each file is written beside its final name and renamed, so a
// reader never sees half a file.
#pragma once

#include <filesystem>

#include "run_record.hpp"

namespace railcosim {

// Returns the folder written. Throws std::runtime_error naming the path.
std::filesystem::path write_run(const std::filesystem::path& out_dir, const RunRecord& run);

std::string summary_json(const RunRecord& run);

}  // namespace railcosim
