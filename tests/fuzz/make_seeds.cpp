// Writes the seed corpus of session_fuzz: real sessions, as frames, so that
// mutations start from every state of the session (used once; the seeds are
// kept in tests/fuzz/corpus).
#include <filesystem>
#include <fstream>

#include "scene.hpp"
#include "subsystem.hpp"
#include "wire.hpp"

using namespace railcosim;

int main(int argc, char** argv) {
  if (argc != 3) return 2;
  const Scene scene = load_scene(argv[1]);
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
  const std::string hello = frame_of(hello_envelope(wire::ROLE_TRACK, scene_fingerprint(scene)));
  int n = 0;
  for (const auto& [split, coupling] :
       {std::pair{Split::kWheelRail, Coupling::kXX}, std::pair{Split::kWheelRail, Coupling::kXT},
        std::pair{Split::kRailSleepers, Coupling::kXX},
        std::pair{Split::kRailSleepers, Coupling::kXT}}) {
    std::string s = hello;
    s += frame_of(configure_envelope(scene, split, coupling, scene.macro_step, scene.tolerance));
    s += frame([](wire::Envelope& e) { e.mutable_initialize(); });
    // The inputs S2 takes, from a real S1.
    Subsystem s1(scene, {split, Side::kS1, coupling, scene.macro_step, scene.tolerance});
    const CouplingData in = s1.initialize().outputs;
    for (long k = 0; k < 3; ++k) {
      s += frame([&](wire::Envelope& e) {
        auto* st = e.mutable_step();
        st->set_step(k);
        st->set_t(static_cast<double>(k) * scene.macro_step);
        st->set_h(scene.macro_step);
        *st->mutable_inputs() = to_wire(in);
      });
    }
    s += frame([](wire::Envelope& e) { e.mutable_save(); });
    s += frame([](wire::Envelope& e) { e.mutable_get_outputs(); });
    s += frame([](wire::Envelope& e) { e.mutable_get_results(); });
    s += frame([](wire::Envelope& e) { e.mutable_shutdown(); });
    std::ofstream(dir / ("session_" + std::to_string(n++)), std::ios::binary) << s;
  }
  std::ofstream(dir / "hello_only", std::ios::binary) << hello;
  return 0;
}
