// The parts of a study's report that compare coupling methods: the cheapest
// method at each accuracy level, and the paper's "almost 10" under both
// restart conventions.
#pragma once

#include <optional>
#include <ostream>
#include <vector>

#include "study/study.hpp"

namespace railcosim::study {

// The accuracy levels of the cheapest-method table (relative L2 error of the
// deflection at t_end against the monolithic run at the same H).
inline const std::vector<double>& accuracy_levels() {
  static const std::vector<double> levels{1e-3, 1e-4, 1e-5};
  return levels;
}

// The co-simulation run ("case" and "sweep" groups) that reaches relative
// error `level` against the monolithic run at the same H in the least wall
// time, if any: what stage 2 reruns over the other transport. (The report's
// answer is per cut, against the converged run: report_front.hpp.)
const StudyRun* cheapest_reaching(const std::vector<StudyRun>& runs, double level);

// What the study's errors are measured against, as the report names it:
// "the co-simulation reference" where its runs were judged against one (a
// participant given by address, a soil of its own: no monolithic model stands
// for its physics), else "the converged monolithic run".
std::string reference_words(const std::vector<StudyRun>& runs);

// Markdown sections: "Largest stable macro step per method" and "Restart convention and the paper's
// 'almost 10'", headed at level `h` ("##", or "###" within a scene variant's section).
void write_method_sections(std::ostream& md, const std::vector<StudyRun>& runs,
                           const std::string& h = "##");

// Jacobi over Gauss–Seidel error of rs-xx at H = 1e-4 s under a restart
// convention, from the study's "restart" runs.
std::optional<double> restart_ratio(const std::vector<StudyRun>& runs, const std::string& restart);

}  // namespace railcosim::study
