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

// Frames with ids counting up across every seed the program writes.
class Frames {
 public:
  std::string of(wire::Envelope e) {
    e.set_id(id_++);
    return encode_frame(e);
  }
  template <class Fill>
  std::string make(Fill fill) {
    wire::Envelope e;
    fill(e);
    return of(e);
  }

 private:
  std::uint64_t id_ = 1;
};

// A participant of a case: its configuration and its inputs at rest.
struct Served {
  SubsystemConfig cfg;
  CouplingData in;
};

// Three macro steps, with held inputs (one step's on their own, in a
// SetInputs), a Save and a Restore after the first; `local` runs the same.
std::string step_frames(const Scene& scene, const CouplingData& in, Subsystem& local, Frames& f) {
  std::string s;
  for (long k = 0; k < 3; ++k) {
    const CouplingData held = scaled(in, 1.0 + 0.01 * static_cast<double>(k));
    if (k == 1) {  // inputs on their own, then the step without them
      local.set_inputs(k, held);
      s += f.make([&](wire::Envelope& e) {
        auto* si = e.mutable_set_inputs();
        si->set_step(k);
        si->set_t(static_cast<double>(k) * scene.macro_step);
        *si->mutable_inputs() = to_wire(held);
      });
      s += f.make([&](wire::Envelope& e) { e.mutable_get_outputs()->set_step(k); });
    } else {
      local.set_inputs(k, held);
    }
    local.step(k);
    s += f.make([&](wire::Envelope& e) {
      auto* st = e.mutable_step();
      st->set_step(k);
      st->set_t(static_cast<double>(k) * scene.macro_step);
      st->set_h(scene.macro_step);
      if (k != 1) *st->mutable_inputs() = to_wire(held);
    });
    if (k == 0) {
      const ParticipantState saved = local.save();
      s += f.make([](wire::Envelope& e) { e.mutable_save(); });
      s += f.make([&](wire::Envelope& e) {
        for (double v : saved.values) e.mutable_restore()->mutable_state()->add_values(v);
      });
    }
  }
  return s;
}

// A whole session of one participant: hello to shutdown.
std::string session_frames(const Scene& scene, const Served& p, Frames& f) {
  const std::string& role = p.cfg.participant.role;
  // The same session in-process gives the state a Restore carries back.
  Subsystem local(scene, p.cfg);
  std::string s = f.of(hello_envelope(role, scene_fingerprint(scene)));
  s += f.of(configure_envelope(scene, p.cfg));
  // Two statics on the way to the static state, as the master iterates.
  for (double scale : {0.9, 1.0}) {
    const CouplingData guess = scaled(p.in, scale);
    local.statics(guess);
    s +=
        f.make([&](wire::Envelope& e) { *e.mutable_statics()->mutable_inputs() = to_wire(guess); });
  }
  local.initialize(p.in);
  s +=
      f.make([&](wire::Envelope& e) { *e.mutable_initialize()->mutable_inputs() = to_wire(p.in); });
  s += step_frames(scene, p.in, local, f);
  s += f.make([](wire::Envelope& e) { e.mutable_get_outputs()->set_step(3); });
  s += f.make([](wire::Envelope& e) { e.mutable_get_results(); });
  s += f.make([](wire::Envelope& e) { e.mutable_shutdown(); });
  return s;
}

// session_0, session_1, ...: (case, participant) for every cut from both
// sides, both coupling types, the rail alone between two cuts, a participant
// with two interfaces. 1 when a case lacks its participant.
int write_sessions(const Scene& scene, const std::filesystem::path& dir, Frames& f) {
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
    Served p;
    for (std::size_t k = 0; k < specs.size(); ++k)
      if (specs[k].role == role) {
        p.cfg.participant = specs[k];
        p.in = at_rest[k];
      }
    if (p.cfg.participant.role != role) {
      std::fprintf(stderr, "make_fuzz_seeds: case %s has no %s participant\n", case_name, role);
      return 1;
    }
    p.cfg.macro_step = scene.macro_step;
    p.cfg.tolerance = scene.tolerance;
    const std::string s = session_frames(scene, p, f);
    std::ofstream(dir / ("session_" + std::to_string(n++)), std::ios::binary) << s;
  }
  return 0;
}

// session_waveform: substep waveforms, recording on, inputs as cubic
// waveforms in a Step and in a SetInputs.
void write_waveform_session(const Scene& scene, const std::filesystem::path& dir, Frames& f) {
  SubsystemConfig cfg;
  cfg.participant = partition(scene, parse_case("rs-xx-gauss-seidel"))[1];
  cfg.macro_step = scene.macro_step;
  cfg.tolerance = scene.tolerance;
  const CouplingData in = static_inputs(scene, "rs-xx-gauss-seidel")[1];
  std::string s = f.of(hello_envelope(cfg.participant.role, scene_fingerprint(scene)));
  s += f.of(configure_envelope(scene, cfg));
  s += f.make([&](wire::Envelope& e) { *e.mutable_initialize()->mutable_inputs() = to_wire(in); });
  s += f.make([](wire::Envelope& e) { e.mutable_record_samples()->set_on(true); });
  for (long k = 0; k < 2; ++k) {
    Waveform w(3, pack_values(in[0]).size());
    for (int j = 0; j <= 3; ++j)
      w.add((static_cast<double>(k) + j / 3.0) * scene.macro_step,
            pack_values(scaled(in, 1.0 + 0.01 * j)[0]));
    if (k == 1)
      s += f.make([&](wire::Envelope& e) {
        e.mutable_set_inputs()->set_step(k);
        *e.mutable_set_inputs()->mutable_waveforms() = to_wire(InputWaveforms{w});
      });
    s += f.make([&](wire::Envelope& e) {
      auto* st = e.mutable_step();
      st->set_step(k);
      st->set_t(static_cast<double>(k) * scene.macro_step);
      st->set_h(scene.macro_step);
      if (k == 0) *st->mutable_waveforms() = to_wire(InputWaveforms{w});
    });
  }
  s += f.make([](wire::Envelope& e) { e.mutable_shutdown(); });
  std::ofstream(dir / "session_waveform", std::ios::binary) << s;
}

// Hostile sessions, each refused by the node with an error reply:
// hostile_nested_lockstep (lock-step windows inside a lock step),
// hostile_wide_waveform (a waveform of 2^27 values per sample and none),
// hostile_deep_key, _header, _array, _inline (a Configure's scene nested 40
// levels deep, past the limit of 32, in each of the ways TOML nests).
void write_hostile_sessions(const Scene& scene, const std::filesystem::path& dir, Frames& f) {
  SubsystemConfig cfg;
  cfg.participant = partition(scene, parse_case("wr-xx-jacobi"))[0];
  cfg.macro_step = scene.macro_step;
  cfg.tolerance = scene.tolerance;
  const CouplingData in = static_inputs(scene, "wr-xx-jacobi")[0];
  const std::string opening = f.of(hello_envelope(cfg.participant.role, scene_fingerprint(scene)));
  const std::string started =
      opening + f.of(configure_envelope(scene, cfg)) +
      f.make([&](wire::Envelope& e) { *e.mutable_initialize()->mutable_inputs() = to_wire(in); });
  std::string s = started;
  for (int k = 0; k < 3; ++k)
    s += f.make([](wire::Envelope& e) {
      e.mutable_window()->set_end_step(10);
      e.mutable_window()->set_lockstep(true);
    });
  std::ofstream(dir / "hostile_nested_lockstep", std::ios::binary) << s;
  s = started + f.make([](wire::Envelope& e) {
    e.mutable_set_inputs()->mutable_waveforms()->add_interfaces()->set_width(1u << 27);
  });
  std::ofstream(dir / "hostile_wide_waveform", std::ios::binary) << s;
  const int depth = 40;
  std::string key = "a", header = "[a", array = "x = ", table = "y = ";
  for (int k = 1; k < depth; ++k) key += ".a", header += ".a";
  array += std::string(depth, '[') + std::string(depth, ']');
  for (int k = 0; k < depth; ++k) table += "{z = ";
  table += "1" + std::string(depth, '}');
  for (const auto& [name, text] :
       {std::pair{"key", key + " = 1"}, std::pair{"header", header + "]"},
        std::pair{"array", array}, std::pair{"inline", table}}) {
    wire::Envelope c = configure_envelope(scene, cfg);
    c.mutable_configure()->set_scene(text + "\n" + scene.text);
    std::ofstream(dir / ("hostile_deep_" + std::string(name)), std::ios::binary)
        << opening + f.of(c);
  }
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
  Frames f;
  if (const int failed = write_sessions(scene, dir, f); failed != 0) return failed;
  write_waveform_session(scene, dir, f);
  // hello_only: a session that ends after its hello.
  std::ofstream(dir / "hello_only", std::ios::binary)
      << f.of(hello_envelope("track", scene_fingerprint(scene)));
  write_hostile_sessions(scene, dir, f);
  return 0;
}
