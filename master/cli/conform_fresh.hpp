// The conformance kit's checks that a participant computes what it is asked
// (docs/protocol.md §18): a participant that replays replies it recorded
// passes every check whose requests it has seen before, so these send
// inputs it has never seen, drawn at random for each run of the kit (the
// seed is printed with a failure; --seed repeats it): the outputs must
// change, and change consistently, with them (to first order, the change
// of the outputs scales with the change of the inputs), and a restore
// followed by new inputs must give what a fresh session given those inputs
// gives.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "cli/conform.hpp"
#include "participant.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim::cli {

struct FreshSubject {
  const Scene& scene;
  const SubsystemConfig& config;
  const ConformOptions& o;
  std::function<CouplingData(long)> inputs;  // the kit's inputs at macro step n
  std::uint64_t seed;                        // of the random inputs
};

// §7: the static state under three loads never sent before: L, L + d and
// L + c d, with a random direction d (up to 0.2 % of each value) and a
// random factor c in [1.5, 4].
// "" when the outputs change and (o(L + c d) - o(L)) equals
// c (o(L + d) - o(L)) within 1 % of its size.
std::string check_static_loads(const FreshSubject& s);

// §10: three macro steps, a save, then the fourth step with inputs A,
// again from the checkpoint with A + d, and again with A + c d; and a fresh
// session that takes the same three steps and the fourth with A + d.
// d is up to 0.1 % of each input: the built-in nodes' steps, nonlinear
// through the Hertz contact, scale to within 0.3 % at that size (1 % at
// 0.5 %). "" when the step with A + d differs from the one with A, scales
// as the statics must (within 1 %), and equals the fresh session's bit for
// bit.
std::string check_restore_new_inputs(const FreshSubject& s);

}  // namespace railcosim::cli
