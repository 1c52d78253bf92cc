#include "study/report_front.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "remote/transport.hpp"
#include "run/run_output.hpp"
#include "study/report_methods.hpp"

namespace railcosim::study {

using run::format_double;
using run::RunRecord;
using run::sci;
using run::write_file_atomically;

namespace {

std::string shortg(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// A candidate of the front for its cut: a co-simulation run of the
// macro-step sweep, or a monolithic run across tolerances.
bool candidate(const StudyRun& r) {
  if (r.method == "monolithic")
    return r.group == "tolerance" || r.group == "case" || r.group == "converged";
  return r.group == "case" || r.group == "sweep";
}

std::string sig3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

}  // namespace

std::string cut_of(const std::string& method) {
  if (method == "monolithic") return method;
  // "wr-xt[...]" or "wr-xx+ss-xt[...]" before the schedule: the cuts are the
  // two letters before each coupling type.
  const std::string base =
      method.substr(0, std::min(method.find("-jacobi"), method.find("-gauss-seidel")));
  std::string cut;
  std::stringstream parts(base);
  for (std::string p; std::getline(parts, p, '+');) {
    if (!cut.empty()) cut.push_back('+');
    cut.append(p, 0, 2);
  }
  return cut;
}

std::vector<FrontRow> study_front(const std::vector<StudyRun>& runs, const std::string& transport) {
  // A co-simulation run's transport as the front groups it (a record that
  // does not say: the study's).
  auto over = [&](const StudyRun& r) {
    return r.method == "monolithic" || r.record.transport.empty() || r.record.transport == transport
               ? transport
               : r.record.transport;
  };
  std::vector<std::pair<std::string, std::string>> columns;  // (cut, transport)
  for (const StudyRun& r : runs)
    if (candidate(r) && r.method != "monolithic") {
      const std::pair<std::string, std::string> c{cut_of(r.method), transport};
      if (std::find(columns.begin(), columns.end(), c) == columns.end()) columns.push_back(c);
    }
  // The columns of runs over another transport, each after its cut's.
  for (const StudyRun& r : runs)
    if (candidate(r) && r.method != "monolithic" && over(r) != transport) {
      const std::pair<std::string, std::string> c{cut_of(r.method), over(r)};
      if (std::find(columns.begin(), columns.end(), c) != columns.end()) continue;
      auto at = std::find_if(columns.begin(), columns.end(),
                             [&](const auto& x) { return x.first == c.first; });
      while (at != columns.end() && at->first == c.first) ++at;
      columns.insert(at, c);
    }
  // A scene whose soil is a participant of its own has no monolithic runs.
  if (std::any_of(runs.begin(), runs.end(),
                  [](const StudyRun& r) { return r.method == "monolithic"; }))
    columns.emplace_back("monolithic", transport);
  std::vector<FrontRow> front;
  for (const auto& [cut, t] : columns)
    for (double level : accuracy_levels()) {
      FrontRow row{cut, t, level, nullptr};
      for (const StudyRun& r : runs) {
        if (!candidate(r) || cut_of(r.method) != cut || over(r) != t || r.record.status != "ok" ||
            r.rel_l2_error_converged > level)
          continue;
        if (!row.run || r.record.wall_s < row.run->record.wall_s) row.run = &r;
      }
      front.push_back(row);
    }
  return front;
}

std::string front_column(const FrontRow& row, const std::string& transport) {
  if (row.cut == "monolithic") return "monolithic (no cut)";
  return row.cut + " cut" +
         (row.transport == transport                  ? ""
          : row.transport == remote::kInprocTransport ? ", in process"
                                                      : ", over " + row.transport);
}

void write_front_csv(const std::filesystem::path& file, const std::vector<FrontRow>& front) {
  std::ostringstream f;
  f << "cut,level,method,macro_step_s,tolerance_m,wall_s,error,transport,folder\n";
  for (const FrontRow& row : front) {
    f << row.cut << "," << format_double(row.level) << ",";
    if (row.run) {
      const RunRecord& x = row.run->record;
      f << row.run->method << "," << format_double(x.macro_step) << ","
        << format_double(row.run->tolerance) << "," << format_double(x.wall_s) << ","
        << format_double(row.run->rel_l2_error_converged) << "," << x.transport << ","
        << row.run->folder;
    } else {  // nothing reaches the level: the transport of the row's candidates
      f << ",,,,," << row.transport << ",";
    }
    f << "\n";
  }
  write_file_atomically(file, f.str());
}

namespace {

// "wr-xx-gauss-seidel, H = 0.001 s: 0.046 s" (or the monolithic run's tolerance).
std::string cell(const FrontRow& row) {
  if (!row.run) return "none reaches it";
  const RunRecord& x = row.run->record;
  std::string s = row.cut == "monolithic"
                      ? "tolerance " + shortg(row.run->tolerance) + " m"
                      : "`" + row.run->method + "`, H = " + shortg(x.macro_step) + " s";
  return s + ": **" + sig3(x.wall_s) + " s**";
}

// Which column is the cheapest at each level: the headline under the table.
// Rows over another transport than the study's are timed without its
// network and take no part (their own sentence follows the table).
std::string fastest_sentence(const std::vector<FrontRow>& front, const std::string& transport) {
  std::vector<std::string> parts;
  bool mono_everywhere = true;
  for (double level : accuracy_levels()) {
    const FrontRow* best = nullptr;
    for (const FrontRow& r : front)
      if (r.level == level && r.run && r.transport == transport &&
          (!best || r.run->record.wall_s < best->run->record.wall_s))
        best = &r;
    if (!best) continue;
    mono_everywhere = mono_everywhere && best->cut == "monolithic";
    parts.push_back(shortg(level) + ": " +
                    (best->cut == "monolithic" ? std::string("the monolithic run")
                                               : "`" + best->run->method + "`"));
  }
  if (parts.empty()) return "No run reaches any of the levels.";
  if (mono_everywhere)
    return "At every level the monolithic run is the fastest: cutting the model buys no speed "
           "here, only the freedom to run the parts apart.";
  std::string s = "The fastest of all at each level:";
  for (std::size_t i = 0; i < parts.size(); ++i) s += (i ? "; " : " ") + parts[i];
  return s + ".";
}

}  // namespace

void write_answer(std::ostream& md, const std::vector<FrontRow>& front,
                  const std::string& transport) {
  std::vector<std::string> columns;
  bool other = false;
  for (const FrontRow& r : front) {
    const std::string c = front_column(r, transport);
    if (std::find(columns.begin(), columns.end(), c) == columns.end()) columns.push_back(c);
    other = other || r.transport != transport;
  }
  const bool mono = std::any_of(front.begin(), front.end(),
                                [](const FrontRow& r) { return r.cut == "monolithic"; });
  md << "**The answer.** The method to use at each cut for a relative error of the rail "
        "deflection at t_end of at most 1e-3, 1e-4 and 1e-5 (against "
     << (mono ? "the converged monolithic run" : "the co-simulation reference")
     << "), and its wall time (co-simulation over `" << transport << "`"
     << (mono ? "; the monolithic run in process" : "")
     << "): the cheapest run of the sweep that "
        "ends `ok` and reaches it. `speed_accuracy.png` draws the same runs bold.\n\n| error at "
        "most |";
  for (const std::string& c : columns) md << " " << c << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < columns.size(); ++i) md << "---|";
  md << "\n";
  for (double level : accuracy_levels()) {
    md << "| " << shortg(level) << " |";
    for (const std::string& c : columns)
      for (const FrontRow& r : front)
        if (front_column(r, transport) == c && r.level == level) md << " " << cell(r) << " |";
    md << "\n";
  }
  md << "\n" << fastest_sentence(front, transport) << "\n\n";
  if (other)
    md << "The columns \"in process\" hold the methods the study runs in process only "
          "(substep waveforms, which over the network take the relayed data plane), the "
          "cheapest of them at each level. Their wall times pay no network, so they are not "
          "compared with the `"
       << transport
       << "` columns (nor named above): compare them with each other and with the in-process "
          "wall times of stage 2 in \"Cheapest method per accuracy\".\n\n";
}

void write_front_table(std::ostream& md, const std::vector<FrontRow>& front,
                       const std::vector<StudyRun>& runs, const std::string& transport,
                       const std::string& h) {
  const std::string other = remote::other_transport(transport);
  md << "\n"
     << h << " Cheapest method per accuracy\n\n"
     << "Per cut, among the runs of the sweep that end `ok`, the one that reaches each relative "
        "error (rail deflection at t_end against "
     << reference_words(runs) << ") in the least wall time over `" << transport << "`"
     << (reference_words(runs) == "the co-simulation reference"
             ? ""
             : " (the monolithic run: across tolerances, in process)")
     << "; the same method and "
     << "H rerun over `" << other << "` where stage 2 ran it. This is the table the report opens "
     << "with and the front `speed_accuracy.png` draws (`front.csv`).\n\n"
     << (std::any_of(front.begin(), front.end(),
                     [&](const FrontRow& r) { return r.transport != transport; })
             ? "The rows over `inproc` of a cut are the runs the study makes in process only "
               "(substep waveforms), timed without the network and compared only with each "
               "other.\n\n"
             : "")
     << "| cut | error at most | method | H (s) | tolerance (m) | error | wall (s) | wall " << other
     << " (s) | iterations per step (mean) | transport "
        "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const FrontRow& row : front) {
    md << "| " << row.cut << " | " << sci(row.level) << " | ";
    if (!row.run) {
      md << "none of the swept runs | | | | | | | " << row.transport << " |\n";
      continue;
    }
    const RunRecord& x = row.run->record;
    std::string again = row.transport == transport ? "–" : "– (in process only)";
    for (const StudyRun& r : runs)
      if (r.group == "other-transport" && r.method == row.run->method &&
          r.record.macro_step == x.macro_step && r.record.status == "ok")
        again = sci(r.record.wall_s);
    md << row.run->method << " | " << shortg(x.macro_step) << " | " << shortg(row.run->tolerance)
       << " | " << sci(row.run->rel_l2_error_converged) << " | " << sci(x.wall_s) << " | " << again
       << " | "
       << (row.cut == "monolithic" ? "–"
           : x.iterations_mean     ? sci(*x.iterations_mean)
                                   : "1 (explicit)")
       << " | " << (row.cut == "monolithic" ? remote::kInprocTransport : x.transport) << " |\n";
  }
}

}  // namespace railcosim::study
