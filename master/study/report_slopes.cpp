#include "study/report_slopes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "run/run_output.hpp"

namespace railcosim::study {
namespace {

int input_order(const std::string& inputs) {
  static const std::vector<std::string> order{"hold",      "linear",    "waveform0",
                                              "waveform1", "waveform2", "waveform3"};
  const auto it = std::find(order.begin(), order.end(), inputs);
  return static_cast<int>(it - order.begin());
}

}  // namespace

std::optional<double> log_log_slope(const std::vector<std::pair<double, double>>& xy) {
  if (xy.size() < 2) return std::nullopt;
  double mx = 0, my = 0;
  for (const auto& [x, y] : xy) {
    mx += std::log(x);
    my += std::log(y);
  }
  const double n = static_cast<double>(xy.size());
  mx /= n;
  my /= n;
  double sxy = 0, sxx = 0;
  for (const auto& [x, y] : xy) {
    sxy += (std::log(x) - mx) * (std::log(y) - my);
    sxx += (std::log(x) - mx) * (std::log(x) - mx);
  }
  if (!(sxx > 0)) return std::nullopt;
  return sxy / sxx;
}

std::vector<SlopeRow> error_slopes(const std::vector<StudyRun>& runs) {
  std::vector<std::string> cases;
  std::vector<SlopeRow> rows;
  for (const StudyRun& r : runs) {
    const run::RunRecord& x = r.record;
    if ((r.group != "case" && r.group != "sweep") || r.method == "monolithic" ||
        x.method != "implicit" || x.accelerator.value_or("") != "iqn-ils" ||
        !verdict::ran_to_end(x) || !(r.rel_l2_error_converged > 0))
      continue;
    if (std::find(cases.begin(), cases.end(), x.case_name) == cases.end())
      cases.push_back(x.case_name);
    auto it = std::find_if(rows.begin(), rows.end(), [&](const SlopeRow& s) {
      return s.case_name == x.case_name && s.inputs == x.inputs;
    });
    if (it == rows.end()) {
      rows.push_back({x.case_name, x.inputs, {}, std::nullopt, {}});
      it = rows.end() - 1;
    }
    // A run judged against a co-simulation reference at its own H measures
    // the reference's convergence, not its error: no point of an order fit.
    const bool own_step = x.reference_kind == "co-simulation" && x.reference_macro_step &&
                          std::abs(*x.reference_macro_step - x.macro_step) <= 1e-9 * x.macro_step;
    if (own_step)
      it->left_out.push_back(x.macro_step);
    else
      it->errors.emplace_back(x.macro_step, r.rel_l2_error_converged);
  }
  auto rank = [&](const SlopeRow& s) {
    return std::pair(std::find(cases.begin(), cases.end(), s.case_name) - cases.begin(),
                     input_order(s.inputs));
  };
  std::stable_sort(rows.begin(), rows.end(),
                   [&](const SlopeRow& a, const SlopeRow& b) { return rank(a) < rank(b); });
  for (SlopeRow& s : rows) {
    std::sort(s.errors.begin(), s.errors.end());
    s.slope = log_log_slope(s.errors);
  }
  rows.erase(
      std::remove_if(rows.begin(), rows.end(), [](const SlopeRow& s) { return s.errors.empty(); }),
      rows.end());
  return rows;
}

void write_slopes_csv(const std::filesystem::path& file, const std::vector<SlopeRow>& rows) {
  std::ostringstream f;
  f << "case,inputs,points,slope,h_min_s,h_max_s\n";
  for (const SlopeRow& s : rows)
    f << s.case_name << "," << s.inputs << "," << s.errors.size() << ","
      << (s.slope ? run::format_double(*s.slope) : std::string()) << ","
      << run::format_double(s.errors.front().first) << ","
      << run::format_double(s.errors.back().first) << "\n";
  run::write_file_atomically(file, f.str());
}

void write_slopes_section(std::ostream& md, const std::vector<SlopeRow>& rows, const std::string& h,
                          const std::string& against) {
  if (rows.empty()) return;
  std::set<double> hs;
  for (const SlopeRow& s : rows)
    for (const auto& e : s.errors) hs.insert(e.first);
  md << "\n"
     << h << " Error against H per input degree\n\n"
     << "Implicit coupling with IQN-ILS: the relative L2 error of the rail deflection at t_end "
        "against "
     << against
     << " at each macro step H, per kind of inputs (linear: "
        "a ramp between the communication points; waveformK: the sender's micro-step outputs "
        "interpolated with degree K, run in process), and the least-squares slope of log(error) "
        "against log(H) over the runs that ran to the end (`error_slopes.csv`). The error "
     << (against == "the co-simulation reference"
             ? "includes the reference's own error (its Richardson estimate in each run's "
               "`summary.json`), a floor no coupling goes below, which flattens the slope at "
               "small H.\n\n"
             : "includes the micro-step tolerance's own error (the monolithic run at the same "
               "tolerance), a floor no coupling goes below, which flattens the slope at small "
               "H.\n\n")
     << "| case | inputs |";
  for (double H : hs) md << " H = " << H << " s |";
  md << " slope |\n|---|---|";
  for (std::size_t i = 0; i <= hs.size(); ++i) md << "---|";
  md << "\n";
  for (const SlopeRow& s : rows) {
    md << "| " << s.case_name << " | " << s.inputs << " |";
    for (double H : hs) {
      const auto it = std::find_if(s.errors.begin(), s.errors.end(),
                                   [&](const auto& e) { return e.first == H; });
      md << " " << (it == s.errors.end() ? std::string("–") : run::sci(it->second)) << " |";
    }
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", s.slope ? *s.slope : 0.0);
    md << " " << (s.slope ? std::string(b) : std::string("–")) << " |\n";
  }
  // Which runs each slope was fitted from, and which were left out.
  std::ostringstream fitted;
  for (const SlopeRow& s : rows) {
    fitted << "\n- " << s.case_name << " " << s.inputs << ": fitted from H =";
    for (std::size_t i = 0; i < s.errors.size(); ++i)
      fitted << (i ? ", " : " ") << s.errors[i].first;
    fitted << " s";
    if (!s.left_out.empty()) {
      fitted << "; left out H =";
      for (std::size_t i = 0; i < s.left_out.size(); ++i)
        fitted << (i ? ", " : " ") << s.left_out[i];
      fitted << " s (judged against a co-simulation reference at its own macro step)";
    }
  }
  md << "\nThe runs each slope is fitted from:" << fitted.str() << "\n";
}

}  // namespace railcosim::study
