// `master study --collect DIR`: the plans' run folders read back into one
// summary.csv and REPORT.md. `master study` ends here too, so a local study
// and a plan run elsewhere are read the same way from the same files.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "log.hpp"
#include "run/run_output.hpp"
#include "study/report.hpp"
#include "study/study.hpp"
#include "study/study_plan.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim::study {
namespace {

namespace fs = std::filesystem;

// summary.json as run_output writes it: an object of strings, numbers, null
// and objects of those; nested keys come out as "outer.inner". A value is
// kept as its text (strings unescaped), null as nullopt.
class FlatJson {
 public:
  FlatJson(std::string text, std::string source)
      : text_(std::move(text)), source_(std::move(source)) {}

  std::map<std::string, std::optional<std::string>> read() {
    std::map<std::string, std::optional<std::string>> out;
    object("", out);
    skip();
    if (pos_ != text_.size()) fail("text after the object");
    return out;
  }

 private:
  void object(const std::string& prefix, std::map<std::string, std::optional<std::string>>& out) {
    expect('{');
    for (bool first = true; !peek('}'); first = false) {
      if (!first) expect(',');
      const std::string key = prefix + string();
      expect(':');
      if (peek('{')) {
        object(key + ".", out);
      } else if (peek('"')) {
        out[key] = string();
      } else if (text_.compare(pos_, 4, "null") == 0) {
        pos_ += 4;
        out[key] = std::nullopt;
      } else {
        const std::size_t begin = pos_;
        while (pos_ < text_.size() && text_[pos_] != ',' && text_[pos_] != '}' &&
               !std::isspace(static_cast<unsigned char>(text_[pos_])))
          ++pos_;
        if (pos_ == begin) fail("expected a value");
        out[key] = text_.substr(begin, pos_ - begin);
      }
    }
    expect('}');
  }
  void skip() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool peek(char c) {
    skip();
    return pos_ < text_.size() && text_[pos_] == c;
  }
  [[noreturn]] void fail(const std::string& what) {
    throw std::invalid_argument(source_ + ": " + what + " at character " + std::to_string(pos_));
  }
  void expect(char c) {
    if (!peek(c)) fail(std::string("expected '") + c + "'");
    ++pos_;
  }
  std::string string() {
    expect('"');
    std::string s;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      char c = text_[pos_++];
      if (c == '\\' && pos_ < text_.size()) {
        c = text_[pos_++];
        if (c == 'u' && pos_ + 4 <= text_.size()) {
          c = static_cast<char>(std::strtol(text_.substr(pos_, 4).c_str(), nullptr, 16));
          pos_ += 4;
        } else if (c == 'n') {
          c = '\n';
        } else if (c == 't') {
          c = '\t';
        } else if (c == 'r') {
          c = '\r';
        }
      }
      s += c;
    }
    expect('"');
    return s;
  }

  std::string text_, source_;
  std::size_t pos_ = 0;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::invalid_argument(p.string() + ": cannot open");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

run::RunRecord record_of(const fs::path& json) {
  const auto m = FlatJson(read_text(json), json.string()).read();
  auto str = [&](const char* k) -> std::optional<std::string> {
    const auto it = m.find(k);
    return it == m.end() ? std::nullopt : it->second;
  };
  auto num = [&](const char* k) -> std::optional<double> {
    const auto s = str(k);
    if (!s) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(s->c_str(), &end);
    if (*end != '\0') throw std::invalid_argument(json.string() + ": " + k + " is not a number");
    return v;
  };
  run::RunRecord r;
  r.case_name = str("case").value_or("");
  r.split = str("split");
  r.coupling = str("coupling");
  r.scheme = str("scheme");
  r.feedthrough = str("feedthrough");
  r.macro_step = num("macro_step_s").value_or(0);
  r.t_end = num("t_end_s").value_or(0);
  r.wall_s = num("wall_s").value_or(0);
  r.macro_steps = static_cast<long>(num("macro_steps").value_or(0));
  for (const auto& [k, v] : m)
    if (k.rfind("micro_steps.", 0) == 0 && v) r.micro_steps[k.substr(12)] = std::atol(v->c_str());
  r.status = str("status").value_or("");
  if (r.status.empty()) throw std::invalid_argument(json.string() + ": no status");
  r.message = str("message").value_or("");
  r.max_abs_error_m = num("max_abs_error_m");
  r.rel_l2_error = num("rel_l2_error");
  r.history_error = num("history_error");
  r.stability = str("stability.verdict").value_or("");
  r.error_growth = num("stability.growth");
  r.error_growth_rate = num("stability.rate_per_s");
  r.probe_time = num("stability.probe_s");
  r.stability_basis = str("stability.basis").value_or("");
  r.spectral_radius = num("stability.rho");
  r.spectral_rate = num("stability.rho_rate_per_s");
  r.matrix_free_rho = num("stability.rho_matrix_free");
  r.matrix_free_rate = num("stability.rho_matrix_free_rate_per_s");
  if (const auto v = num("stability.matrix_free_steps"))
    r.matrix_free_steps = static_cast<long>(*v);
  r.reference_kind = str("reference.kind").value_or("");
  r.reference_note = str("reference.note").value_or("");
  r.reference_folder = str("reference.folder").value_or("");
  r.reference_macro_step = num("reference.macro_step_s");
  r.defect_growth = num("stability.defect_growth");
  r.defect_rate = num("stability.defect_rate_per_s");
  r.defect_grows = str("stability.defect_grows").value_or("") == "true";
  r.transport = str("transport").value_or("");
  r.restart = str("restart").value_or("consistent");
  r.method = str("method").value_or("explicit");
  r.inputs = str("inputs").value_or("hold");
  r.accelerator = str("accelerator");
  r.iterations_mean = num("iterations.mean");
  if (const auto v = num("iterations.max")) r.iterations_max = static_cast<long>(*v);
  if (const auto v = num("iterations.not_converged_steps"))
    r.not_converged_steps = static_cast<long>(*v);
  return r;
}

bool has_deflection(const run::RunRecord& r) {
  return verdict::ran_to_end(r);
}

// deflection.csv: x_m,w_m per rail node.
void read_deflection(const fs::path& file, run::RunRecord& r) {
  std::istringstream in(read_text(file));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    if (comma == std::string::npos)
      throw std::invalid_argument(file.string() + ": bad row " + line);
    r.x.push_back(std::strtod(line.c_str(), nullptr));
    r.deflection.push_back(std::strtod(line.c_str() + comma + 1, nullptr));
  }
}

// What a run folder holds, or a record with status "missing" saying why
// there is nothing to read.
run::RunRecord read_run(const fs::path& dir, const PlannedRun& run) {
  const fs::path folder = dir / run.folder;
  const fs::path json = folder / "summary.json";
  auto missing = [&](const std::string& why) {
    run::RunRecord r;
    r.case_name = run.case_name;
    r.macro_step = run.macro_step;
    r.transport = run.transport;
    r.status = "missing";
    r.message = why;
    return r;
  };
  if (!fs::exists(folder))
    return missing("no folder " + run.folder + ": the run has not been done");
  if (!fs::exists(json))
    return missing("no summary.json in " + run.folder + ": the run has not finished");
  try {
    run::RunRecord r = record_of(json);
    if (has_deflection(r)) read_deflection(folder / "deflection.csv", r);
    return r;
  } catch (const std::exception& e) {
    return missing(std::string("unreadable: ") + e.what());
  }
}

void read_plan_runs(const fs::path& dir, const StudyPlan& plan, CollectedStudy& c) {
  for (const PlannedRun& p : plan.runs) {
    StudyRun s;
    s.group = p.group;
    s.folder = p.folder;
    s.variant = p.variant;
    s.method = p.method;
    s.tolerance = p.tolerance;
    s.record = read_run(dir, p);
    c.runs.push_back(std::move(s));
  }
}

}  // namespace

CollectedStudy collect_study(const fs::path& dir, const std::string& figure_script, bool write) {
  StudyPlan plan = read_plan(plan_file(dir, 1));
  plan.out = dir;  // wherever the folder is now
  CollectedStudy c;
  read_plan_runs(dir, plan, c);
  const std::size_t stage1 = c.runs.size();
  bool stage1_complete = true;
  for (const StudyRun& s : c.runs)
    stage1_complete = stage1_complete && s.record.status != "missing";

  // Stage 2 needs the wall times of stage 1: planned once stage 1 is all
  // there, and kept (a later collection reads the same plan).
  std::string stage2_note;
  if (fs::exists(plan_file(dir, 2))) {
    StudyPlan second = read_plan(plan_file(dir, 2));
    CollectedStudy c2;
    read_plan_runs(dir, second, c2);
    bool none = true;
    for (const StudyRun& s : c2.runs) none = none && s.record.status == "missing";
    if (none && !c2.runs.empty()) {
      c.stage2_pending = true;
    } else {
      c.runs.insert(c.runs.end(), c2.runs.begin(), c2.runs.end());
    }
  } else if (stage1_complete) {
    StudyPlan second = other_transport_plan(plan, c.runs);
    write_plan(second);
    c.stage2_pending = !second.runs.empty();
  }

  // The converged reference of each variant, and every run against it.
  std::map<std::string, const run::RunRecord*> converged;
  for (std::size_t i = 0; i < stage1; ++i)
    if (c.runs[i].group == "converged" && has_deflection(c.runs[i].record))
      converged[c.runs[i].variant] = &c.runs[i].record;
  for (StudyRun& s : c.runs) {
    c.failed += s.record.status == "failed";
    c.missing += s.record.status == "missing";
    c.not_run += s.record.status == "not_run";
    // A run judged against its co-simulation reference (a participant the
    // monolithic model cannot stand for) is charted by its error against it.
    const auto it = converged.find(s.variant);
    if (s.record.reference_kind == "co-simulation") {
      s.rel_l2_error_converged = s.record.rel_l2_error.value_or(0);
    } else if (it != converged.end() && has_deflection(s.record) &&
               s.record.deflection.size() == it->second->deflection.size())
      s.rel_l2_error_converged =
          verdict::deflection_error(s.record.deflection, it->second->deflection).rel_l2;
  }
  if (!write) return c;
  write_summary_csv(dir / "summary.csv", c.runs);
  StudyReportInfo info;
  info.dir = dir;
  info.source_scene = plan.source_scene;
  info.transport = plan.transport;
  info.converged_tolerance = plan.converged_tolerance;
  info.sweeps = plan.sweeps;
  info.figure_script = figure_script;
  info.stage2_pending = c.stage2_pending;
  info.stage1_complete = stage1_complete;
  for (const PlannedRun& p : plan.runs)
    if (std::find_if(info.variants.begin(), info.variants.end(),
                     [&](const auto& v) { return v.first == p.variant; }) == info.variants.end())
      info.variants.emplace_back(p.variant, p.variant_dir);
  write_report(info, c.runs);
  return c;
}

}  // namespace railcosim::study
