// The text of a study plan: its command lines, written and read back.
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "remote/transport.hpp"
#include "run/run_output.hpp"
#include "study/study_plan.hpp"

namespace railcosim::study {
namespace {

namespace fs = std::filesystem;

// A word the shell reads back as it is: quoted when it needs to be.
std::string shell_word(const std::string& s) {
  const bool plain = !s.empty() && s.find_first_not_of(
                                       "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnop"
                                       "qrstuvwxyz0123456789_-+=.,/:@%") == std::string::npos;
  if (plain) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  q += '\'';
  return q;
}

std::string join(const std::vector<double>& v) {
  std::string s;
  for (double x : v) {
    if (!s.empty()) s += ',';
    s += run::format_double(x);
  }
  return s;
}

double number(const std::string& s, const std::string& where) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') throw std::invalid_argument(where + ": not a number: " + s);
  return v;
}

std::vector<double> numbers(const std::string& s, const std::string& where) {
  std::vector<double> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) out.push_back(number(item, where));
  return out;
}

// and backslashes; what shell_word writes).
std::vector<std::string> shell_words(const std::string& line, const std::string& where) {
  std::vector<std::string> out;
  std::string cur;
  bool in_word = false, quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '\'') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '\'') {
      quoted = in_word = true;
    } else if (c == '\\' && i + 1 < line.size()) {
      cur += line[++i];
      in_word = true;
    } else if (c == ' ' || c == '\t') {
      if (in_word) out.push_back(cur);
      cur.clear();
      in_word = false;
    } else {
      cur += c;
      in_word = true;
    }
  }
  if (quoted) throw std::invalid_argument(where + ": an unclosed quote");
  if (in_word) out.push_back(cur);
  return out;
}

// A run line's `master run` options back into a run (what command_line writes).
PlannedRun parse_command(const std::vector<std::string>& w, const fs::path& out,
                         const std::string& where) {
  if (w.size() < 2 || w[1] != "run")
    throw std::invalid_argument(where + ": expected 'MASTER run OPTIONS'");
  PlannedRun r;
  std::string out_dir;
  for (std::size_t i = 2; i < w.size(); ++i) {
    const std::string& k = w[i];
    if (i + 1 >= w.size()) throw std::invalid_argument(where + ": " + k + " without a value");
    const std::string& v = w[++i];
    const std::string what = where + ": " + k;
    if (k == "--scene") {
      const std::string base = out.string() + "/";
      r.scene = v.rfind(base, 0) == 0 ? v.substr(base.size()) : v;
    } else if (k == "--case") {
      r.case_name = v;
    } else if (k == "--macro-step" && v.find('=') != std::string::npos) {
      // A cut's window, after the finest: k H.
      const double window = number(v.substr(v.find('=') + 1), what);
      r.cut_windows[v.substr(0, v.find('='))] =
          r.macro_step > 0 ? std::lround(window / r.macro_step) : 0;
    } else if (k == "--macro-step") {
      r.macro_step = number(v, what);
    } else if (k == "--tolerance") {
      r.tolerance = number(v, what);
    } else if (k == "--transport") {
      r.transport = remote::parse_transport(v, what).name();
    } else if (k == "--feedthrough") {
      r.feedthrough = parse_feedthrough(v).value_or(Feedthrough::kLagged);
    } else if (k == "--coupling") {
      r.coupling.method = engine::parse_coupling_method(v, what);
    } else if (k == "--inputs") {
      r.coupling.inputs = engine::parse_input_mode(v, what);
    } else if (k == "--accelerator") {
      r.coupling.accelerator.kind = engine::parse_accelerator(v, what);
    } else if (k == "--relaxation") {
      r.coupling.accelerator.relaxation = number(v, what);
    } else if (k == "--max-iterations") {
      r.coupling.max_iterations = static_cast<int>(number(v, what));
    } else if (k == "--convergence") {
      r.coupling.convergence = number(v, what);
    } else if (k == "--reused-windows") {
      r.coupling.accelerator.windows_reused = static_cast<int>(number(v, what));
    } else if (k == "--reference-step") {
      r.reference_step = number(v, what);
    } else if (k == "--node") {
      // the plan's "#% node" settings name the nodes
    } else if (k == "--out") {
      out_dir = v;
    } else {
      throw std::invalid_argument(what + ": not an option a plan writes");
    }
  }
  if (r.case_name.empty() || r.scene.empty() || out_dir.empty())
    throw std::invalid_argument(where + ": the command lacks --scene, --case or --out");
  return r;
}

}  // namespace

fs::path plan_file(const fs::path& out, int stage) {
  return out / (stage == 1 ? "plan.txt" : "plan-" + std::to_string(stage) + ".txt");
}

std::string command_line(const StudyPlan& plan, const PlannedRun& r) {
  const fs::path prefix = fs::path(r.folder).parent_path();
  std::string c = shell_word(plan.master);
  c += " run --scene ";
  c += shell_word((plan.out / r.scene).string());
  c += " --case " + r.case_name + " --macro-step " + run::format_double(r.macro_step) +
       " --tolerance " + run::format_double(r.tolerance);
  for (const auto& [cut, k] : r.cut_windows)
    c += " --macro-step " + cut + "=" + run::format_double(r.macro_step * static_cast<double>(k));
  if (r.case_name != "monolithic") {
    c += " --transport " + r.transport;
    for (const std::string& n : plan.nodes) c += " --node " + shell_word(n);
    if (r.reference_step > 0) c += " --reference-step " + run::format_double(r.reference_step);
    if (r.feedthrough == Feedthrough::kResolved) c += " --feedthrough resolved";
    const engine::CouplingOptions& k = r.coupling;
    if (!k.is_plain()) {
      c += " --coupling " + to_string(k.method) + " --inputs " + to_string(k.inputs);
      if (k.method == engine::CouplingMethod::kImplicit)
        c += " --accelerator " + to_string(k.accelerator.kind) + " --relaxation " +
             run::format_double(k.accelerator.relaxation) + " --max-iterations " +
             std::to_string(k.max_iterations) + " --convergence " +
             run::format_double(k.convergence) + " --reused-windows " +
             std::to_string(k.accelerator.windows_reused);
    }
  }
  c += " --out ";
  c += shell_word((prefix.empty() ? plan.out : plan.out / prefix).string());
  return c;
}

std::string plan_text(const StudyPlan& p) {
  std::ostringstream s;
  s << "# railcosim study plan, stage " << p.stage << " (format " << p.format << ").\n"
    << "# Each line after the settings is one complete `master run` command: run them in any\n"
    << "# order, anywhere that sees the same files, then `master study --collect " << p.out.string()
    << "`.\n"
    << "# The \" #% ...\" after a command is a shell comment saying what the run is.\n"
    << "#% format = " << p.format << "\n"
    << "#% stage = " << p.stage << "\n"
    << "#% scene = " << p.source_scene << "\n"
    << "#% out = " << p.out.string() << "\n"
    << "#% transport = " << p.transport << "\n"
    << "#% macro_steps = " << (p.macro_steps.empty() ? "default" : join(p.macro_steps)) << "\n"
    << "#% tolerances = " << join(p.tolerances) << "\n"
    << "#% converged_tolerance = " << run::format_double(p.converged_tolerance) << "\n";
  for (const SweepAxis& a : p.sweeps) {
    s << "#% sweep = " << a.key << "=";
    for (std::size_t i = 0; i < a.values.size(); ++i) s << (i ? "," : "") << a.values[i];
    s << "\n";
  }
  for (const std::string& n : p.nodes) s << "#% node = " << n << "\n";
  s << "#% runs = " << p.runs.size() << "\n";
  for (const PlannedRun& r : p.runs)
    s << command_line(p, r) << " #% folder=" << r.folder << " group=" << r.group
      << " method=" << r.method << " variant=" << r.variant << " variant_dir=" << r.variant_dir
      << "\n";
  return s.str();
}

void write_plan(const StudyPlan& plan, const fs::path& copy) {
  std::error_code ec;
  for (const auto& [rel, text] : plan.scene_files) {
    const fs::path f = plan.out / rel;
    fs::create_directories(f.parent_path(), ec);
    if (ec)
      throw std::runtime_error("cannot create " + f.parent_path().string() + ": " + ec.message());
    run::write_file_atomically(f, text);
  }
  fs::create_directories(plan.out, ec);
  if (ec) throw std::runtime_error("cannot create " + plan.out.string() + ": " + ec.message());
  const std::string text = plan_text(plan);
  const fs::path own = plan_file(plan.out, plan.stage);
  run::write_file_atomically(own, text);
  if (!copy.empty() && !fs::equivalent(copy, own, ec)) run::write_file_atomically(copy, text);
}

StudyPlan read_plan(const fs::path& file) {
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument(file.string() +
                                ": cannot open (is this the folder a study plan was written to?)");
  StudyPlan p;
  int line_no = 0;
  bool saw_format = false;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    const std::string where = file.string() + ":" + std::to_string(line_no);
    if (line.rfind("#% ", 0) == 0) {
      const auto eq = line.find(" = ");
      if (eq == std::string::npos)
        throw std::invalid_argument(where + ": expected '#% key = value'");
      const std::string key = line.substr(3, eq - 3), value = line.substr(eq + 3);
      if (key == "format") {
        saw_format = true;
        if (value != std::to_string(kPlanFormat))
          throw std::invalid_argument(where + ": plan format " + value + "; this master reads " +
                                      std::to_string(kPlanFormat));
      } else if (key == "stage") {
        p.stage = static_cast<int>(number(value, where));
      } else if (key == "scene") {
        p.source_scene = value;
      } else if (key == "out") {
        p.out = value;
      } else if (key == "transport") {
        p.transport = remote::parse_transport(value, where + ": transport").name();
      } else if (key == "macro_steps") {
        if (value != "default") p.macro_steps = numbers(value, where);
      } else if (key == "tolerances") {
        p.tolerances = numbers(value, where);
      } else if (key == "converged_tolerance") {
        p.converged_tolerance = number(value, where);
      } else if (key == "sweep") {
        p.sweeps.push_back(parse_sweep(value));
      } else if (key == "node") {
        p.nodes.push_back(value);
      }  // "runs" is for people; later formats may add keys
      continue;
    }
    if (line.empty() || line[0] == '#') continue;
    const auto mark = line.find(" #% ");
    if (mark == std::string::npos)
      throw std::invalid_argument(where + ": a run line must end in ' #% folder=... group=...'");
    std::map<std::string, std::string> f;
    std::stringstream words(line.substr(mark + 4));
    for (std::string w; words >> w;) {
      const auto eq = w.find('=');
      if (eq != std::string::npos) f[w.substr(0, eq)] = w.substr(eq + 1);
    }
    for (const char* k : {"folder", "group", "method"})
      if (f[k].empty()) throw std::invalid_argument(where + ": the run has no " + k + "=");
    const std::vector<std::string> words_of_command = shell_words(line.substr(0, mark), where);
    PlannedRun r = parse_command(words_of_command, p.out, where);
    p.master = words_of_command.front();  // stage 2 calls the same program
    r.folder = f["folder"];
    r.group = f["group"];
    r.method = f["method"];
    r.variant = f["variant"];
    r.variant_dir = f["variant_dir"];
    p.runs.push_back(std::move(r));
  }
  if (!saw_format)
    throw std::invalid_argument(file.string() + ": not a study plan (no '#% format' line)");
  return p;
}

}  // namespace railcosim::study
