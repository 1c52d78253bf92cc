// The reference a co-simulation is judged against where the product cannot
// build the monolithic model: a participant served by a node given by
// address (which may run physics of its own behind the scene's name), or a
// scene whose soil is `external`.
//
// The reference is the product's best co-simulation of the same
// participants: the same case (its split, so the same participants, served
// by the same nodes), implicit coupling converged to kReferenceConvergence
// with IQN-ILS, its inputs substep waveforms of degree 3 (falling back to
// linear ramps for participants that take no waveforms, and to held inputs
// for those that take no ramps either, then of first order), at a finer macro
// step H_ref = H / k. Its own error is estimated by Richardson
// extrapolation from a second reference run at 2 H_ref: for a method of
// order p the difference of the two, over 2^p - 1, estimates the error of
// the finer one (p = 2: Newmark's trapezoidal rule, and a converged coupling
// with inputs at least linear over the step, are second order).
//
// The verdict sees the model only through a maker of those two runs
// (ReferenceMaker): the run module makes them with its own runs of the
// participants (run/cosim_reference.hpp), and the verdict decides whether
// they can serve and judges the run against them.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "scene.hpp"
#include "verdict/run_record.hpp"

namespace railcosim::verdict {

// The implicit iterations of the reference converge to this relative
// residual (coupling_options.hpp), a hundredth of the default.
inline constexpr double kReferenceConvergence = 1e-10;
inline constexpr int kReferenceMaxIterations = 100;
// The order assumed by the Richardson estimate of the reference's error
// (held inputs, where a participant takes no ramps: 1).
inline constexpr int kReferenceOrder = 2;
// A reference whose estimated error is over this fraction of a bound the
// run is judged by (cosim.amplification_threshold, kMaxDeflectionError)
// cannot tell ok from inaccurate: the run is then not judged.
inline constexpr double kReferenceErrorShare = 0.5;

// The run's rows every `k`-th row of `fine` (its history and coupling
// history; its final fields as they are): a run at H_ref seen at k H_ref.
RunRecord every_kth_row(const RunRecord& fine, long k);

// The reference runs of a cut set, made once for every run that is judged
// against them: by a key the maker gives (run/cosim_reference.cpp: scene
// file, cuts and their types, reference step, tolerance, transport and data
// plane). The schedule is not in the key: the reference is a converged
// implicit coupling, run Jacobi, so the Jacobi and Gauss-Seidel methods of
// one cut set (and their feedthroughs, inputs and couplings) share one
// reference.
class CosimReferences {
 public:
  struct Made {
    RunRecord fine, coarse;       // at H_ref and 2 H_ref
    std::string note;             // how they were made (linear inputs instead of a waveform)
    std::string why_not;          // why they cannot serve; "" when they can
    std::string folder;           // where `fine` was written, relative to the root; "" if not
    int order = kReferenceOrder;  // of its inputs: 1 where it had to hold them
  };
  // The pair of `key`, made by `make` the first time it is asked for.
  const Made& get(const std::string& key, const std::function<Made()>& make);
  // Writes each reference made from now on (its finer run, as a run folder)
  // below ROOT/references/H_<H_ref>/<cuts>/, e.g. references/H_5e-05/ss-xt/.
  void write_below(const std::filesystem::path& root) { root_ = root; }
  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
  struct Entry {
    std::once_flag once;
    Made made;
  };
  std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Entry>> entries_;
};

// The model's side of the co-simulation reference.
struct ReferenceMaker {
  // The key of the reference runs at the macro step H_ref (CosimReferences).
  std::function<std::string(double H_ref)> key;
  // The two runs at H_ref and 2 H_ref, or why they cannot be made.
  std::function<CosimReferences::Made(double H_ref)> make;
};

// Judges a run at macro step H against the co-simulation reference made by
// `maker` at the macro step `reference_step` (0: H / 2; else H / k, k the
// nearest whole number of reference steps in H, at least 1), after its
// stability without its model (judge_without_model: the map and the probe
// would build the built-in participants). Where no reference can be made
// (a reference run fails, diverges or does not converge) or its estimated
// error is too large to judge by, the status becomes "not_judged" and the
// message says why. With `shared`, the reference runs are made once for
// every run asking for the same ones.
void assess_against_reference(RunRecord& run, const Scene& scene, double H, double reference_step,
                              const ReferenceMaker& maker, CosimReferences* shared = nullptr);

}  // namespace railcosim::verdict
