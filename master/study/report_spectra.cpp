#include "study/report_spectra.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace railcosim::study {
namespace {

struct Band {
  double centre = 0, rms = 0;
};

std::string fixed(double v, int digits) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

std::string db(double rms) {
  return rms > 0 ? fixed(20.0 * std::log10(rms), 1) : "–";
}

}  // namespace

void write_spectra_section(std::ostream& md, const std::filesystem::path& dir,
                           const std::string& figure, const std::string& h) {
  std::ifstream in(dir / "monolithic" / "spectra.csv");
  if (!in) return;
  std::string line;
  std::getline(in, line);  // signal,band,centre_Hz,lower_Hz,upper_Hz,rms,level_dB
  // Per band: the contact force, and the energy mean over the sleepers of
  // the ballast forces.
  std::map<int, Band> contact;
  std::map<int, std::pair<double, int>> ballast;  // sum of rms^2, count
  std::map<int, double> centre;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string signal, band, c, lo, hi, rms;
    if (!std::getline(s, signal, ',') || !std::getline(s, band, ',') || !std::getline(s, c, ',') ||
        !std::getline(s, lo, ',') || !std::getline(s, hi, ',') || !std::getline(s, rms, ','))
      continue;
    const int b = std::stoi(band);
    centre[b] = std::stod(c);
    const double r = std::stod(rms);
    if (signal == "contact_force_N") contact[b] = {std::stod(c), r};
    if (signal.rfind("ballast_force_", 0) == 0) {
      ballast[b].first += r * r;
      ballast[b].second += 1;
    }
  }
  if (centre.empty()) return;
  md << "\n"
     << h
     << " Spectra\n\nOne-third-octave band levels (dB re 1 N, band RMS) of the monolithic "
        "run: the total contact force and, where the scene writes them, the forces into the "
        "ballast under the sleepers (energy mean over the sleepers): what a soil solver "
        "receives. Every run's bands are in its `spectra.csv`.\n\n";
  if (!figure.empty()) md << "![spectra](" << figure << ")\n\n";
  md << "| band centre (Hz) | contact force (dB) | ballast force, mean (dB) |\n|---|---|---|\n";
  for (const auto& [b, f] : centre) {
    const auto k = contact.find(b);
    const auto q = ballast.find(b);
    md << "| " << fixed(f, f < 100 ? 1 : 0) << " | "
       << (k == contact.end() ? "–" : db(k->second.rms)) << " | "
       << (q == ballast.end() || q->second.second == 0
               ? "–"
               : db(std::sqrt(q->second.first / q->second.second)))
       << " |\n";
  }
}

}  // namespace railcosim::study
