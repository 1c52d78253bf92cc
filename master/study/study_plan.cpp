#include "study/study_plan.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "remote/transport.hpp"
#include "run/run_output.hpp"
#include "scene.hpp"
#include "scene_text.hpp"
#include "study/report_methods.hpp"
#include "toml_nesting.hpp"

namespace railcosim::study {
namespace {

namespace fs = std::filesystem;

std::string short_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string read_text(const std::string& p) {
  std::ifstream in(p);
  if (!in) throw std::invalid_argument(p + ": cannot open");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A folder name for a value: characters a shell and a file system take as they are.
std::string folder_word(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return out;
}

// A value given on the command line, as TOML: of the type the scene gives
// the key, else a whole number, a number, true/false, or a string.
SceneEdit swept(const std::string& key, const std::string& value, const toml::node* old) {
  const char* begin = value.c_str();
  char* end = nullptr;
  auto bad = [&](const char* what) {
    std::string m = "--sweep ";
    m += key;
    m += '=';
    m += value;
    m += ": the scene gives ";
    m += key;
    m += " as ";
    m += what;
    return std::invalid_argument(m);
  };
  errno = 0;
  const long long i = std::strtoll(begin, &end, 10);
  const bool is_int = !value.empty() && *end == '\0' && errno == 0;
  const double d = std::strtod(begin, &end);
  const bool is_num = !value.empty() && *end == '\0' && std::isfinite(d);
  const bool is_bool = value == "true" || value == "false";
  if (old && old->is_integer()) {
    if (!is_int) throw bad("a whole number");
    return {key, static_cast<std::int64_t>(i)};
  }
  if (old && old->is_floating_point()) {
    if (!is_num) throw bad("a number");
    return {key, d};
  }
  if (old && old->is_boolean()) {
    if (!is_bool) throw bad("true or false");
    return {key, value == "true"};
  }
  if (old && old->is_string()) return {key, value};
  if (old) throw bad("a table or an array, which cannot be swept");
  if (is_int) return {key, static_cast<std::int64_t>(i)};
  if (is_num) return {key, d};
  if (is_bool) return {key, value == "true"};
  return {key, value};
}

// The scene text with each KEY set to VALUE (the scene's parser then
// rejects keys it does not know, naming them).
std::string with_values(const std::string& text, const std::string& source,
                        const std::vector<std::pair<std::string, std::string>>& values) {
  check_toml_nesting(text, source);
  const toml::table root = toml::parse(text, source);
  std::vector<SceneEdit> edits;
  for (const auto& [key, value] : values)
    edits.push_back(swept(key, value, root.at_path(key).node()));
  try {
    return edit_scene_text(text, source, edits) + "\n";
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--sweep: ") + e.what());
  }
}

struct Variant {
  std::string label, dir;  // "key=v;key=v" and its folder ("" without a sweep)
  std::vector<std::pair<std::string, std::string>> values;
};

std::vector<Variant> variants_of(const std::vector<SweepAxis>& axes) {
  std::vector<Variant> out{{}};
  for (const SweepAxis& a : axes) {
    std::vector<Variant> next;
    for (const Variant& v : out)
      for (const std::string& value : a.values) {
        Variant w = v;
        w.values.emplace_back(a.key, value);
        if (!w.label.empty()) w.label += ';';
        w.label += a.key;
        w.label += '=';
        w.label += value;
        if (!w.dir.empty()) w.dir += '+';
        std::string word = a.key;
        word += '_';
        word += value;
        w.dir += folder_word(word);
        next.push_back(std::move(w));
      }
    out = std::move(next);
  }
  return out;
}

bool divides(double H, double t_end) {
  const double n = t_end / H;
  return std::abs(n - std::round(n)) <= 1e-9 * n && n >= 1;
}

bool has_cut(const CaseSpec& spec, const std::string& cut) {
  return std::any_of(spec.cuts.begin(), spec.cuts.end(), [&cut](const CutChoice& c) {
    return cut_kinds()[static_cast<std::size_t>(c.cut)].name == cut;
  });
}

// The folder of a method below its group's: CASE, resolved/CASE, or
// COUPLING/CASE (e.g. implicit-linear-iqn-ils/wr-xx-jacobi).
std::string method_folder(const Method& m) {
  std::string f;
  if (m.feedthrough == Feedthrough::kResolved) f = "resolved/";
  if (!m.coupling.is_plain()) f = m.coupling.label() + "/";
  for (const auto& [cut, k] : m.cut_windows)
    if (k > 1) f += cut + "-at-" + std::to_string(k) + "H/";
  return f + m.spec.name();
}

// The methods of the cases named (--cases); throws std::invalid_argument
// for a name that is none of them.
std::vector<Method> methods_of_cases(const std::vector<Method>& methods,
                                     const std::vector<std::string>& cases) {
  std::vector<Method> kept;
  for (const std::string& c : cases) {
    const std::size_t before = kept.size();
    for (const Method& m : methods)
      if (m.spec.name() == c) kept.push_back(m);
    if (kept.size() == before)
      throw std::invalid_argument("--cases: " + c + " is not a co-simulation case of the scene");
  }
  return kept;
}

// Adds the runs of one scene variant to a plan.
struct VariantRuns {
  StudyPlan& plan;
  const StudyOptions& o;
  const Variant& v;
  std::string prefix;                         // the variant's folder and '/' ("" without a sweep)
  std::map<std::string, long> scene_windows;  // scene_cut_windows() of the variant's scene

  // One run of `group` in the folder `where` below the variant's; no method:
  // the monolithic model.
  void add(const std::string& group, const std::string& where, const Method* m, double H,
           double tol, const std::string& scene_file) const {
    PlannedRun r;
    r.variant = v.label;
    r.variant_dir = v.dir;
    r.group = group;
    r.scene = scene_file;
    r.method = m ? m->label() : "monolithic";
    r.case_name = m ? m->spec.name() : "monolithic";
    if (m) {
      r.feedthrough = m->feedthrough;
      r.coupling = m->coupling;
      // The scene's windows for the case's cuts, at H unless the method
      // gives its own.
      for (const auto& [cut, k] : scene_windows)
        if (has_cut(m->spec, cut)) r.cut_windows[cut] = 1;
      for (const auto& [cut, k] : m->cut_windows) r.cut_windows[cut] = k;
    }
    r.transport = m ? run_transport(m->coupling, o.transport) : o.transport;
    r.folder = prefix + where + (m ? method_folder(*m) : "monolithic");
    r.macro_step = H;
    r.tolerance = tol;
    plan.runs.push_back(std::move(r));
  }
};

// The variant's scene; the file of a variant that sets values goes into the
// plan as `scene_rel`.
Scene variant_scene(const VariantRuns& to, const std::string& base, const std::string& scene_path,
                    const std::string& scene_rel) {
  if (to.v.dir.empty()) return parse_scene(base, scene_path);
  const std::string text = with_values(base, scene_path, to.v.values);
  Scene scene;
  try {
    scene = parse_scene(text, (to.o.out / scene_rel).string());
  } catch (const SceneError& e) {
    std::string m = "--sweep ";
    m += to.v.label;
    m += ": ";
    m += e.what();
    throw SceneError(m);
  }
  to.plan.scene_files.emplace_back(
      scene_rel, "# " + scene_path + " with " + to.v.label + " (--sweep)\n" + text);
  return scene;
}

// The paper's "almost 10" at the rail/sleepers cut with X-X under both
// restart conventions, 10 fixed micro steps per macro step of 1e-4 s.
void add_restart_runs(const VariantRuns& to, const Scene& scene, const std::string& base,
                      const std::string& scene_path) {
  const auto names = case_names(scene);
  if (!to.o.restart_check || !std::count(names.begin(), names.end(), "rs-xx-jacobi") ||
      !divides(1e-4, scene.end_time))
    return;
  const Variant& v = to.v;
  for (const char* restart : {"consistent", "carry"}) {
    const std::string dir = to.prefix + "restart/" + restart + "/";
    const std::string text = with_values(
        base, scene_path,
        v.values.empty() ? std::vector<std::pair<std::string, std::string>>{} : v.values);
    std::vector<std::pair<std::string, std::string>> fixed{{"simulation.micro_steps", "10"},
                                                           {"simulation.restart", restart}};
    to.plan.scene_files.emplace_back(
        dir + "scene.toml", "# " + scene_path + (v.label.empty() ? "" : " with " + v.label) +
                                ", 10 fixed micro steps, restart = " + restart + "\n" +
                                with_values(text, scene_path, fixed));
    for (const char* c : {"rs-xx-jacobi", "rs-xx-gauss-seidel"}) {
      Method m;
      m.spec = parse_case(c);
      to.add("restart", "restart/" + std::string(restart) + "/", &m, 1e-4, scene.tolerance,
             dir + "scene.toml");
    }
  }
}

// One variant's runs, in plan order: the cases at the scene's H, the sweep
// of H, the restart check, the tolerances and the converged reference.
void add_variant(StudyPlan& plan, const StudyOptions& o, const Variant& v, const std::string& base,
                 const std::string& scene_path) {
  VariantRuns to{plan, o, v, v.dir.empty() ? "" : v.dir + "/", {}};
  const std::string scene_rel = to.prefix + "scene.toml";
  const Scene scene = variant_scene(to, base, scene_path, scene_rel);
  to.scene_windows = scene_cut_windows(scene);
  std::vector<double> sweep = o.macro_steps.empty() ? default_macro_steps(scene) : o.macro_steps;
  for (double H : sweep)
    if (!divides(H, scene.end_time))
      throw std::invalid_argument(
          "--macro-steps: " + short_number(H) + " s does not divide the end time " +
          short_number(scene.end_time) + " s of " + (v.dir.empty() ? scene_path : v.label));
  std::vector<Method> methods = o.methods.empty() ? methods_for(scene) : o.methods;
  if (!o.cases.empty()) methods = methods_of_cases(methods, o.cases);
  if (!o.nodes.empty()) methods = methods_with_nodes(scene, methods, o.nodes);
  if (scene.started_soil() != nullptr) methods = methods_with_started_soil(scene, methods);
  fit_to_fmus(scene, methods, sweep);
  // A soil of its own (FE, Green's functions, external) has no monolithic model,
  // and a node given by address runs physics of its own behind its role.
  const bool monolithic = !scene.outside_model() && o.nodes.empty();
  if (monolithic) to.add("case", "", nullptr, scene.macro_step, scene.tolerance, scene_rel);
  for (const Method& m : methods)
    to.add("case", "", &m, scene.macro_step, scene.tolerance, scene_rel);

  for (double H : sweep) {
    if (H == scene.macro_step) continue;  // the cases are that column of the sweep
    for (const Method& m : methods)
      if (m.coupling.method != engine::CouplingMethod::kImplicit || H >= o.implicit_min_macro_step)
        to.add("sweep", "sweep/H_" + short_number(H) + "/", &m, H, scene.tolerance, scene_rel);
  }
  if (!monolithic) {  // every run against one co-simulation reference step
    const double smallest =
        std::min(*std::min_element(sweep.begin(), sweep.end()), scene.macro_step);
    for (PlannedRun& r : plan.runs)
      if (r.case_name != "monolithic" && r.variant == v.label) r.reference_step = smallest;
  } else {  // the restart check's cases need not hold the given roles
    add_restart_runs(to, scene, base, scene_path);
  }
  if (!monolithic) return;
  for (double tol : o.tolerances)
    to.add("tolerance", "sweep/tol_" + short_number(tol) + "/", nullptr, scene.macro_step, tol,
           scene_rel);
  to.add("converged", "converged/", nullptr, scene.macro_step, o.converged_tolerance, scene_rel);
}

}  // namespace

SweepAxis parse_sweep(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw std::invalid_argument("--sweep " + text +
                                ": expected KEY=V1,V2,..., e.g. vehicle.speed_kmh=160,200");
  SweepAxis a;
  a.key = text.substr(0, eq);
  std::stringstream values(text.substr(eq + 1));
  for (std::string v; std::getline(values, v, ',');) {
    if (v.empty() || v.find_first_of(" \t\n;'\"") != std::string::npos)
      throw std::invalid_argument("--sweep " + text + ": value '" + v +
                                  "' is empty or holds a space, quote or ';'");
    a.values.push_back(v);
  }
  return a;
}

StudyPlan make_plan(const std::string& scene_path, const StudyOptions& o) {
  StudyPlan plan;
  plan.out = o.out;
  plan.source_scene = scene_path;
  plan.master = o.master_program.empty() ? "master" : o.master_program;
  plan.transport = o.transport;
  plan.macro_steps = o.macro_steps;
  plan.tolerances = o.tolerances;
  plan.converged_tolerance = o.converged_tolerance;
  plan.sweeps = o.sweeps;
  plan.nodes = o.nodes;

  const std::string base = read_text(scene_path);
  // The user's scene must be sound before anything else.
  // A [coupling] table may give cuts their windows (the study's multirate
  // methods); anything else it sets is how master run couples one case.
  SceneCoupling coupling = parse_scene(base, scene_path).coupling;
  coupling.wr_macro_step = coupling.rs_macro_step = coupling.ss_macro_step = std::nullopt;
  coupling.given = false;
  if (!(coupling == SceneCoupling{}))
    throw std::invalid_argument(
        scene_path +
        ": the scene's [coupling] table sets how master run couples one case; a study runs "
        "every coupling method itself and would have its runs take the table's values: study "
        "a copy of the scene without it (the cuts' windows, CUT_macro_step, may stay)");
  plan.scene_files.emplace_back("scene.toml", base);
  for (const Variant& v : variants_of(o.sweeps)) add_variant(plan, o, v, base, scene_path);
  return plan;
}

StudyPlan other_transport_plan(const StudyPlan& stage1, const std::vector<StudyRun>& runs) {
  StudyPlan p = stage1;
  p.stage = 2;
  p.runs.clear();
  p.scene_files.clear();
  // The other transport cannot reach a node given by address, nor hold a
  // soil that is a program of its own (no monolithic run was planned).
  const bool has_monolithic =
      std::any_of(stage1.runs.begin(), stage1.runs.end(),
                  [](const PlannedRun& r) { return r.case_name == "monolithic"; });
  if (!stage1.nodes.empty() || !has_monolithic) return p;
  const std::string other = remote::other_transport(stage1.transport);
  std::map<std::string, std::vector<StudyRun>> by_variant;
  std::map<std::string, std::vector<std::size_t>> index;  // into stage1.runs
  std::vector<std::string> order;
  for (std::size_t i = 0; i < runs.size() && i < stage1.runs.size(); ++i) {
    // Runs over another transport than the study's (substep waveforms, in
    // process only) are neither compared in wall time with it nor rerun.
    if (stage1.runs[i].transport != stage1.transport) continue;
    const std::string& v = stage1.runs[i].variant;
    if (!by_variant.count(v)) order.push_back(v);
    by_variant[v].push_back(runs[i]);
    index[v].push_back(i);
  }
  for (const std::string& v : order) {
    std::set<std::size_t> done;
    for (double level : accuracy_levels()) {
      const std::vector<StudyRun>& vr = by_variant[v];
      const StudyRun* best = cheapest_reaching(vr, level);
      if (!best) continue;
      const std::size_t i = index[v][static_cast<std::size_t>(best - vr.data())];
      if (!done.insert(i).second) continue;
      PlannedRun r = stage1.runs[i];
      r.group = "other-transport";
      r.transport = other;
      const std::string prefix = r.variant_dir.empty() ? "" : r.variant_dir + "/";
      std::string below = r.folder.substr(prefix.size());  // [sweep/H_x/]METHOD_FOLDER
      if (below.rfind("sweep/", 0) == 0) below = below.substr(below.find('/', 6) + 1);
      r.folder =
          prefix + "other-transport/" + other + "/H_" + short_number(r.macro_step) + "/" + below;
      p.runs.push_back(std::move(r));
    }
  }
  return p;
}

}  // namespace railcosim::study
