#include "run/execute.hpp"

#include <optional>
#include <stdexcept>

#include "model.hpp"
#include "remote/inproc_fmu.hpp"
#include "run/assess.hpp"
#include "run/cosim_reference.hpp"
#include "run/matrix_free.hpp"
#include "run/run_output.hpp"
#include "verdict/evaluation.hpp"
#include "verdict/stability.hpp"

namespace railcosim::run {
namespace {

// Why the case's participants cannot be judged: "the soil FMU cannot save
// its state" where the scene maps a role to an FMU that does not (neither
// the stability measure nor the reference, both of which restart steps,
// can be made); "" otherwise.
std::string unjudgeable(const Scene& scene, const CaseSpec& spec, const RunOptions& o) {
  for (const ParticipantSpec& p : partition(scene, spec)) {
    const auto a =
        remote::fmu_abilities(scene, subsystem_config(scene, p, o.macro_step, o.tolerance));
    if (a && !a->state) return "the " + p.role + " FMU cannot save its state";
  }
  return "";
}

RunRecord made_run(const RunJob& job, const RunOptions& o) {
  const Scene& scene = *job.scene;
  if (job.spec.monolithic) return run_monolithic(scene, o);
  const remote::SceneTransport t =
      remote::make_transport(remote::parse_transport(job.transport, "transport"), scene, job.nodes);
  // A node the user started may run physics of its own behind the scene's
  // name: neither the monolithic model nor the map can stand for it.
  bool given_node = false;
  const remote::ParticipantFactory factory = [&](const SubsystemConfig& c) {
    if (job.nodes.given.count(c.participant.role) != 0) given_node = true;
    return t.factory(c);
  };
  RunRecord r = run_cosim(scene, job.spec, o, factory, t.name);
  // A soil the master starts (FE, Green's functions) writes its measures
  // into the run's folder, which reference runs would overwrite: it is
  // judged when a reference step is asked for (the study's runs; it is then
  // started without an output folder).
  const bool started = scene.started_soil() != nullptr;
  if (o.judge.mode == JudgeMode::kNone) {
    r.reference_kind = "none";
    verdict::judge_unmeasured(r, "--judge none");
    return r;
  }
  if (const std::string why = unjudgeable(scene, job.spec, o); !why.empty()) {
    r.reference_kind = "none";
    r.spectral_note = why;
    verdict::judge_unmeasured(r, why);
    return r;
  }
  if (o.judge.mode == JudgeMode::kStability) {
    r.reference_kind = "none";
    const bool own_model = !given_node && !scene.outside_model();
    if (own_model) {
      assess_growth(r, scene, job.spec, o);
    } else {
      // As the full judgement does (assess_against_reference): the verdict
      // of a model the verdict cannot build, with the measure's rho (also
      // where it found no growth) and the defect check along the run.
      judge_growth_matrix_free(r, scene, job.spec, o, t.name, job.nodes);
      verdict::judge_without_model(r, o.macro_step);
    }
    verdict::judge_unmeasured(r, "errors not measured (--judge stability)");
    return r;
  }
  if (given_node || scene.soil_model == "external" || scene.outside_vehicle() ||
      (started && job.reference_step > 0)) {
    judge_growth_matrix_free(r, scene, job.spec, o, t.name, job.nodes);
    assess_against_cosim(r, scene, job.spec, o, factory, t.name, job.reference_step,
                         job.cosim_references);
  } else if (started) {
    r.reference_kind = "none";
    r.reference_note =
        "the soil is a program the master starts, which writes its measures into the run's "
        "folder: no co-simulation reference is made for it (--reference-step makes one, and "
        "the soil then writes no measures)";
  } else {
    r.reference_kind = "monolithic";
    assess(r, job.reference(), scene, job.spec, o);
  }
  return r;
}

}  // namespace

RunOutcome execute(const RunJob& job) {
  RunOutcome out;
  RunOptions o = job.options;
  // The writer outlives a failure, so that a failed run keeps its history.
  std::optional<RunWriter> writer;
  long steps_done = 0;  // for the summary of a run that fails
  o.on_progress = [&job, &steps_done](long done, long total) {
    steps_done = done;
    if (job.on_progress) job.on_progress(done, total);
  };
  try {
    writer.emplace(job.out, job.folder);
    out.dir = writer->dir();
    if (job.on_folder) job.on_folder(writer->dir());
    o.on_row = [&writer](const HistoryRow& row) { writer->row(row); };
    o.on_channels = [&writer](const std::vector<std::string>& extra) { writer->channels(extra); };
    out.record = made_run(job, o);
  } catch (const std::exception& e) {
    out.error = e.what();
  }
  if (out.error.empty()) {
    // A file that cannot be written leaves a summary saying so, then throws.
    try {
      writer->finish(out.record);
    } catch (const std::exception& e) {
      out.error = e.what();
    }
    return out;
  }
  out.record = failed_record(*job.scene, job.spec, o, job.transport, out.error);
  out.record.macro_steps = steps_done;
  try {
    if (writer) {
      writer->finish(out.record);
    } else {
      RunWriter again(job.out, job.folder);
      out.dir = again.dir();
      again.finish(out.record);
    }
  } catch (const std::exception& e) {
    out.error += "; no summary written: ";
    out.error += e.what();
  }
  return out;
}

}  // namespace railcosim::run
