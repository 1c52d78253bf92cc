// The spectra section of a study's report: one-third-octave band levels of
// the contact force and of the forces into the ballast (what a soil solver
// receives), from the monolithic run's spectra.csv.
#pragma once

#include <filesystem>
#include <ostream>

namespace railcosim {

// Writes "## Spectra" when OUT/monolithic/spectra.csv exists; `figure` says
// whether figures/spectra.png was drawn.
void write_spectra_section(std::ostream& md, const std::filesystem::path& out, bool figure);

}  // namespace railcosim
