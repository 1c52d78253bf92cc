// Writes the seed corpus of session_fuzz: whole sessions, as frames, so that
// mutations start from every state of a session, for participants of every
// kind (vehicle, track, rail, soil; upper and lower sides of every cut, X-X
// and X-T). Run once with a scene that has a soil; the seeds are kept in
// tests/fuzz/corpus:
//
//   make_fuzz_seeds scenes/soil.toml tests/fuzz/corpus
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <memory>

#include "../cosim_support.hpp"
#include "engine/coupled_statics.hpp"
#include "engine/schedule.hpp"
#include "scene.hpp"
#include "subsystem.hpp"
#include "wire.hpp"

using namespace railcosim;

namespace {

// The inputs of every participant of a case at its coupled static state
// (values a real session sees), in load order.
std::vector<CouplingData> static_inputs(const Scene& scene, const std::string& case_name) {
  return test::inproc_case_at_statics(scene, case_name).statics.inputs;
}

CouplingData scaled(CouplingData in, double scale) {
  for (InterfaceData& i : in)
    for (auto* v : {&i.displacement, &i.velocity, &i.force})
      for (double& x : *v) x *= scale;
  return in;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_fuzz_seeds SCENE_WITH_SOIL OUT_DIR\n");
    return 2;
  }
  const Scene scene = load_scene(argv[1]);
  if (!scene.builtin_soil()) {
    std::fprintf(stderr, "make_fuzz_seeds: %s has no built-in soil; use scenes/soil.toml\n",
                 argv[1]);
    return 2;
  }
  const std::filesystem::path dir = argv[2];
  std::filesystem::create_directories(dir);
  std::uint64_t id = 1;
  auto frame_of = [&](wire::Envelope e) {
    e.set_id(id++);
    return encode_frame(e);
  };
  auto frame = [&](auto fill) {
    wire::Envelope e;
    fill(e);
    return frame_of(e);
  };
  // (case, participant): every cut from both sides, both coupling types, the
  // rail alone between two cuts, a participant with two interfaces.
  const std::pair<const char*, const char*> sessions[] = {
      {"wr-xt-jacobi", "vehicle"},    {"wr-xx+ss-xt-gauss-seidel", "track"},
      {"rs-xx-jacobi", "track"},      {"rs-xt-gauss-seidel", "vehicle"},
      {"ss-xt-jacobi", "soil"},       {"wr-xx+ss-xx-jacobi", "soil"},
      {"wr-xt+rs-xx-jacobi", "rail"},
  };
  int n = 0;
  for (const auto& [case_name, role] : sessions) {
    const std::vector<ParticipantSpec> specs = partition(scene, parse_case(case_name));
    const std::vector<CouplingData> at_rest = static_inputs(scene, case_name);
    SubsystemConfig cfg;
    CouplingData in;
    for (std::size_t p = 0; p < specs.size(); ++p)
      if (specs[p].role == role) {
        cfg.participant = specs[p];
        in = at_rest[p];
      }
    if (cfg.participant.role != role) {
      std::fprintf(stderr, "make_fuzz_seeds: case %s has no %s participant\n", case_name, role);
      return 1;
    }
    cfg.macro_step = scene.macro_step;
    cfg.tolerance = scene.tolerance;
    // The same session in-process gives the state a Restore carries back.
    Subsystem local(scene, cfg);
    std::string s = frame_of(hello_envelope(role, scene_fingerprint(scene)));
    s += frame_of(configure_envelope(scene, cfg));
    // Two statics on the way to the static state, as the master iterates.
    for (double scale : {0.9, 1.0}) {
      const CouplingData guess = scaled(in, scale);
      local.statics(guess);
      s += frame(
          [&](wire::Envelope& e) { *e.mutable_statics()->mutable_inputs() = to_wire(guess); });
    }
    local.initialize(in);
    s += frame([&](wire::Envelope& e) { *e.mutable_initialize()->mutable_inputs() = to_wire(in); });
    for (long k = 0; k < 3; ++k) {
      const CouplingData held = scaled(in, 1.0 + 0.01 * static_cast<double>(k));
      if (k == 1) {  // inputs on their own, then the step without them
        local.set_inputs(k, held);
        s += frame([&](wire::Envelope& e) {
          auto* si = e.mutable_set_inputs();
          si->set_step(k);
          si->set_t(static_cast<double>(k) * scene.macro_step);
          *si->mutable_inputs() = to_wire(held);
        });
        s += frame([&](wire::Envelope& e) { e.mutable_get_outputs()->set_step(k); });
      } else {
        local.set_inputs(k, held);
      }
      local.step(k);
      s += frame([&](wire::Envelope& e) {
        auto* st = e.mutable_step();
        st->set_step(k);
        st->set_t(static_cast<double>(k) * scene.macro_step);
        st->set_h(scene.macro_step);
        if (k != 1) *st->mutable_inputs() = to_wire(held);
      });
      if (k == 0) {
        const ParticipantState saved = local.save();
        s += frame([](wire::Envelope& e) { e.mutable_save(); });
        s += frame([&](wire::Envelope& e) {
          for (double v : saved.values) e.mutable_restore()->mutable_state()->add_values(v);
        });
      }
    }
    s += frame([](wire::Envelope& e) { e.mutable_get_outputs()->set_step(3); });
    s += frame([](wire::Envelope& e) { e.mutable_get_results(); });
    s += frame([](wire::Envelope& e) { e.mutable_shutdown(); });
    std::ofstream(dir / ("session_" + std::to_string(n++)), std::ios::binary) << s;
  }
  // Substep waveforms: recording on, inputs as cubic waveforms in a Step
  // and in a SetInputs.
  {
    SubsystemConfig cfg;
    cfg.participant = partition(scene, parse_case("rs-xx-gauss-seidel"))[1];
    cfg.macro_step = scene.macro_step;
    cfg.tolerance = scene.tolerance;
    const CouplingData in = static_inputs(scene, "rs-xx-gauss-seidel")[1];
    std::string s = frame_of(hello_envelope(cfg.participant.role, scene_fingerprint(scene)));
    s += frame_of(configure_envelope(scene, cfg));
    s += frame([&](wire::Envelope& e) { *e.mutable_initialize()->mutable_inputs() = to_wire(in); });
    s += frame([](wire::Envelope& e) { e.mutable_record_samples()->set_on(true); });
    for (long k = 0; k < 2; ++k) {
      Waveform w(3, pack_values(in[0]).size());
      for (int j = 0; j <= 3; ++j)
        w.add((static_cast<double>(k) + j / 3.0) * scene.macro_step,
              pack_values(scaled(in, 1.0 + 0.01 * j)[0]));
      if (k == 1)
        s += frame([&](wire::Envelope& e) {
          e.mutable_set_inputs()->set_step(k);
          *e.mutable_set_inputs()->mutable_waveforms() = to_wire(InputWaveforms{w});
        });
      s += frame([&](wire::Envelope& e) {
        auto* st = e.mutable_step();
        st->set_step(k);
        st->set_t(static_cast<double>(k) * scene.macro_step);
        st->set_h(scene.macro_step);
        if (k == 0) *st->mutable_waveforms() = to_wire(InputWaveforms{w});
      });
    }
    s += frame([](wire::Envelope& e) { e.mutable_shutdown(); });
    std::ofstream(dir / "session_waveform", std::ios::binary) << s;
  }
  std::ofstream(dir / "hello_only", std::ios::binary)
      << frame_of(hello_envelope("track", scene_fingerprint(scene)));
  return 0;
}
