// The spectra section of a study's report: one-third-octave band levels of
// the contact force and of the forces into the ballast (what a soil solver
// receives), from the monolithic run's spectra.csv.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

namespace railcosim::study {

// Writes "H Spectra" (H: "##" or "###") when DIR/monolithic/spectra.csv
// exists; `figure` is the drawn figure's path relative to the report, or empty.
void write_spectra_section(std::ostream& md, const std::filesystem::path& dir,
                           const std::string& figure, const std::string& h);

}  // namespace railcosim::study
