#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "model.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"
#include "wire.hpp"

namespace railcosim {
namespace protocol_test {

Scene soil_scene() {
  return load_scene(test::source_path("scenes/soil.toml"));
}

wire::Envelope sample_step_report() {
  StepResult r;
  r.outputs.resize(2);
  r.outputs[0].displacement = {1.5e-3, -2.25e-4, 0.1 + 0.2};  // values that print inexactly
  r.outputs[0].velocity = {0.0, -0.0, 1e-300};
  r.outputs[1].force = {110362.5};
  r.max_abs_displacement = 1.9e-3;
  r.finite = true;
  r.history = {1.97e-3, 110362.5};
  wire::Envelope e;
  e.set_id(42);
  *e.mutable_step_report() = to_wire(r, 123, 0.0123);
  return e;
}

TEST(Frames, RoundTripThroughTheDecoderInPieces) {
  const wire::Envelope a = sample_step_report();
  wire::Envelope b;
  b.set_id(7);
  b.mutable_step()->set_step(5);
  b.mutable_step()->set_h(1e-4);
  const std::string bytes = encode_frame(a) + encode_frame(b);
  FrameDecoder dec;
  std::vector<wire::Envelope> got;
  // Feed one byte at a time: frames may arrive split anywhere.
  for (char c : bytes) {
    dec.feed(&c, 1);
    wire::Envelope e;
    while (dec.next(e) == FrameDecoder::Status::kFrame) got.push_back(e);
  }
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].SerializeAsString(), a.SerializeAsString());
  EXPECT_EQ(got[1].SerializeAsString(), b.SerializeAsString());
  EXPECT_EQ(dec.buffered(), 0u);
}

TEST(Frames, CouplingDataSurvivesBitwise) {
  const wire::Envelope e = sample_step_report();
  FrameDecoder dec;
  const std::string bytes = encode_frame(e);
  dec.feed(bytes.data(), bytes.size());
  wire::Envelope back;
  ASSERT_EQ(dec.next(back), FrameDecoder::Status::kFrame);
  const StepResult r = from_wire(back.step_report());
  ASSERT_EQ(r.outputs.size(), 2u);
  EXPECT_EQ(r.outputs[0].displacement, (std::vector<double>{1.5e-3, -2.25e-4, 0.1 + 0.2}));
  EXPECT_TRUE(std::signbit(r.outputs[0].velocity[1]));
  EXPECT_EQ(r.outputs[0].velocity[2], 1e-300);
  EXPECT_TRUE(r.outputs[0].force.empty());
  // Each interface keeps its own quantities: nothing leaks between them.
  EXPECT_TRUE(r.outputs[1].displacement.empty());
  EXPECT_TRUE(r.outputs[1].velocity.empty());
  EXPECT_EQ(r.outputs[1].force, (std::vector<double>{110362.5}));
  EXPECT_EQ(r.history, (std::vector<double>{1.97e-3, 110362.5}));
  EXPECT_EQ(back.step_report().step(), 123);
  EXPECT_EQ(back.step_report().t(), 0.0123);
}

// Bitwise equality of doubles, NaN payloads and signed zeros included.
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(Frames, SubstepSamplesAndInputWaveformsSurviveBitwise) {
  wire::Envelope e = sample_step_report();
  OutputSamples samples;
  for (int k = 0; k <= 3; ++k) {
    CouplingData d(2);
    d[0].displacement = {0.1 * k + 0.2, -0.0, 1e-310 * k};
    d[1].force = {110362.5 / 3.0 * k};
    samples.push_back({(123 + k / 3.0) * 1e-4, d});
  }
  to_wire(samples, e.mutable_step_report());
  InputWaveforms waves;
  waves.emplace_back(3, 2);
  for (int k = 0; k <= 4; ++k) waves[0].add(1e-4 * (5 + k / 7.0), {std::sqrt(k + 0.5), -0.0});
  waves.emplace_back(0, 1);
  waves[1].add(5e-4, {1.0 / 3.0});
  wire::Envelope step;
  *step.mutable_step()->mutable_waveforms() = to_wire(waves);
  FrameDecoder dec;
  const std::string bytes = encode_frame(e) + encode_frame(step);
  dec.feed(bytes.data(), bytes.size());
  wire::Envelope back, back_step;
  ASSERT_EQ(dec.next(back), FrameDecoder::Status::kFrame);
  ASSERT_EQ(dec.next(back_step), FrameDecoder::Status::kFrame);
  const OutputSamples got = samples_from_wire(back.step_report());
  ASSERT_EQ(got.size(), samples.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_TRUE(same_bits({got[i].t}, {samples[i].t})) << i;
    ASSERT_EQ(got[i].outputs.size(), 2u);
    EXPECT_TRUE(same_bits(got[i].outputs[0].displacement, samples[i].outputs[0].displacement));
    EXPECT_TRUE(got[i].outputs[0].velocity.empty());
    EXPECT_TRUE(same_bits(got[i].outputs[1].force, samples[i].outputs[1].force));
  }
  ASSERT_TRUE(back_step.step().has_waveforms());
  EXPECT_FALSE(back_step.step().has_inputs());
  const InputWaveforms w = from_wire(back_step.step().waveforms());
  ASSERT_EQ(w.size(), 2u);
  for (std::size_t j = 0; j < w.size(); ++j) {
    EXPECT_EQ(w[j].degree(), waves[j].degree());
    EXPECT_EQ(w[j].width(), waves[j].width());
    ASSERT_EQ(w[j].samples(), waves[j].samples());
    for (std::size_t i = 0; i < w[j].samples(); ++i) {
      EXPECT_TRUE(same_bits({w[j].time(i)}, {waves[j].time(i)}));
      EXPECT_TRUE(same_bits(w[j].sample(i), waves[j].sample(i)));
    }
    // So the receiver evaluates exactly what the sender would.
    EXPECT_TRUE(same_bits(w[j].at(5.3e-4), waves[j].at(5.3e-4)));
  }
}

TEST(Frames, AMalformedInputWaveformIsABadRequest) {
  auto refused = [](const wire::InputWaveforms& w, const std::string& message) {
    try {
      from_wire(w);
      ADD_FAILURE() << "accepted: " << message;
    } catch (const ProtocolError& e) {
      EXPECT_EQ(e.code(), wire::Error::BAD_REQUEST);
      EXPECT_EQ(std::string(e.what()), message);
    }
  };
  wire::InputWaveforms w;
  auto* a = w.add_interfaces();
  a->set_degree(4);
  refused(w, "waveform of input interface 0: degree 4 is not 0 to 3");
  a->set_degree(1);
  a->set_width(2);
  a->add_times(0.0);
  a->add_values(1.0);
  refused(w, "waveform of input interface 0: 1 values for 1 samples of 2");
  a->add_values(std::nan(""));
  refused(w, "waveform of input interface 0: sample 0 is not finite");
  a->set_values(1, 2.0);
  a->add_times(0.0);
  a->add_values(1.0);
  a->add_values(2.0);
  EXPECT_THROW(from_wire(w), ProtocolError);  // times that do not increase
}

TEST(Frames, OversizedFramesAreRefusedBothWays) {
  wire::Envelope big;
  auto* st = big.mutable_state();
  for (int i = 0; i < 1000; ++i) st->add_values(i);
  EXPECT_THROW(encode_frame(big, 100), ProtocolError);
  const std::string bytes = encode_frame(big);
  FrameDecoder dec(100);
  dec.feed(bytes.data(), 8);  // the header alone condemns it
  wire::Envelope e;
  EXPECT_EQ(dec.next(e), FrameDecoder::Status::kTooLarge);
  EXPECT_EQ(dec.announced(), bytes.size() - kFrameHeaderBytes);
}

TEST(Frames, GarbageIsABadFrame) {
  const std::string bytes = std::string("\0\0\0\5", 4) + "\xff\xff\xff\xff\xff";
  FrameDecoder dec;
  dec.feed(bytes.data(), bytes.size());
  wire::Envelope e;
  EXPECT_EQ(dec.next(e), FrameDecoder::Status::kBadFrame);
}

TEST(Frames, ATruncatedFrameWaitsForTheRest) {
  const std::string bytes = encode_frame(sample_step_report());
  FrameDecoder dec;
  dec.feed(bytes.data(), bytes.size() - 1);
  wire::Envelope e;
  EXPECT_EQ(dec.next(e), FrameDecoder::Status::kNeedMore);
  dec.feed(bytes.data() + bytes.size() - 1, 1);
  EXPECT_EQ(dec.next(e), FrameDecoder::Status::kFrame);
}

// The published FNV-1a 64-bit test vectors (Fowler, Noll and Vo; the
// reference test suite of the FNV home page, isthe.com/chongo/tech/comp/fnv).
TEST(Fingerprint, Fnv1a64MatchesThePublishedVectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ull);
}

// The fingerprint the protocol document gives for scenes/soil.toml, in its
// text and in its worked example, is the one the master sends for that scene.
TEST(Fingerprint, TheProtocolDocumentsExampleIsTheSoilScenes) {
  std::ifstream in(test::source_path("docs/protocol.md"));
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const std::string want = std::to_string(scene_fingerprint(soil_scene()));
  std::vector<std::string> quoted;
  for (const std::string key : {"`scenes/soil.toml` gives", "scene_fingerprint:"})
    for (auto at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
      const auto from = text.find_first_not_of(" \n", at + key.size());
      quoted.push_back(text.substr(from, text.find_first_not_of("0123456789", from) - from));
    }
  ASSERT_EQ(quoted.size(), 2u) << "the document's fingerprint examples moved";
  for (const std::string& q : quoted) EXPECT_EQ(q, want);
}

// The scene a built-in node gets in Configure: the text the master parsed,
// parsed again by the node into the same scene, with the same fingerprint.
Scene through_configure(const Scene& s) {
  SubsystemConfig config;
  config.participant = partition(s, parse_case("wr-xx-jacobi")).front();
  config.macro_step = s.macro_step;
  config.tolerance = s.tolerance;
  return scene_from_wire(configure_envelope(s, config).configure());
}

TEST(Conversions, SceneRoundTripsAndItsFingerprintSeesEveryChange) {
  for (const Scene& s : {test::paper_scene(), soil_scene()}) {
    Scene back = through_configure(s);
    EXPECT_EQ(back.source, "the master's scene");
    EXPECT_EQ(scene_fingerprint(back), scene_fingerprint(s));
    back.source = s.source;
    EXPECT_TRUE(back == s) << s.name << ": the node's scene differs from the master's";
  }
  const Scene s = test::paper_scene();
  const Scene changed = with_keys(s, {{"railpad.damping", std::nextafter(s.pad_damping, 1e9)}});
  EXPECT_EQ(changed.pad_damping, std::nextafter(s.pad_damping, 1e9));
  EXPECT_NE(scene_fingerprint(changed), scene_fingerprint(s));
  EXPECT_EQ(through_configure(changed).pad_damping, changed.pad_damping);
}

// A field set in code after parsing would not reach the node: the master
// refuses to send such a scene rather than run two different ones.
TEST(Conversions, ASceneChangedBehindItsTextIsNotSent) {
  Scene s = test::paper_scene();
  s.pad_damping *= 2;
  try {
    through_configure(s);
    FAIL() << "sent";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("changed after it was read"), std::string::npos)
        << e.what();
  }
}

TEST(Conversions, AnInvalidSceneOnTheWireIsABadScene) {
  const Scene s = test::paper_scene();
  wire::Configure c;
  // The canonical text's [sleepers] table with a negative mass.
  std::string text = s.text;
  const auto mass = text.find("mass = ", text.find("[sleepers]"));
  ASSERT_NE(mass, std::string::npos);
  text.replace(mass, text.find('\n', mass) - mass, "mass = -1.0");
  c.set_scene(text);
  try {
    scene_from_wire(c);
    FAIL() << "no error";
  } catch (const ProtocolError& e) {
    EXPECT_EQ(e.code(), wire::Error::BAD_SCENE);
    EXPECT_NE(std::string(e.what()).find("sleepers.mass"), std::string::npos) << e.what();
  }
}

// A scene naming a profile file: the file travels with the text, and a node
// that is not handed it names the file.
TEST(Conversions, TheProfileFileTravelsWithTheScene) {
  const std::string dir = testing::TempDir();
  {
    std::ofstream csv(dir + "/bumps.csv");
    csv << "x_m,r_m\n-100,0\n0,0.001\n100,0\n";
  }
  std::ifstream paper(test::source_path("scenes/paper.toml"));
  std::stringstream text;
  text << paper.rdbuf() << "\n[irregularity]\nmodel = \"csv\"\nfile = \"bumps.csv\"\n";
  const Scene s = parse_scene(text.str(), dir + "/bumps.toml");
  ASSERT_EQ(s.files.count("bumps.csv"), 1u);
  const Scene back = through_configure(s);
  EXPECT_EQ(back.irregularity.table_r, s.irregularity.table_r);
  EXPECT_EQ(scene_fingerprint(back), scene_fingerprint(s));
  wire::Configure bare;
  bare.set_scene(s.text);
  try {
    scene_from_wire(bare);
    FAIL() << "no error";
  } catch (const ProtocolError& e) {
    EXPECT_EQ(e.code(), wire::Error::BAD_SCENE);
    EXPECT_NE(std::string(e.what()).find("bumps.csv: not among the files"), std::string::npos)
        << e.what();
  }
}

// Every interface of every participant of these cases, through the wire and
// back: the node rebuilds exactly what the master partitioned.
TEST(Conversions, EveryInterfaceRoundTrips) {
  const Scene scene = soil_scene();
  int checked = 0;
  for (const char* name : {"wr-xx-jacobi", "wr-xt-jacobi", "rs-xx-jacobi", "rs-xt-jacobi",
                           "ss-xx-jacobi", "ss-xt-jacobi", "wr-xt+rs-xx+ss-xt-jacobi"}) {
    for (const ParticipantSpec& p : partition(scene, parse_case(name))) {
      for (const InterfaceSpec& i : p.interfaces) {
        SCOPED_TRACE(std::string(name) + ", " + p.role + ", " + i.kind().name);
        const wire::Interface w = to_wire(scene, i);
        const InterfaceSpec back = from_wire(w);
        EXPECT_EQ(back.cut, i.cut);
        EXPECT_EQ(back.side, i.side);
        EXPECT_EQ(back.coupling, i.coupling);
        EXPECT_EQ(back.peer_role, i.peer_role);
        EXPECT_EQ(back.receives(), i.receives());
        EXPECT_EQ(back.sends(), i.sends());
        const std::vector<double> x(w.x().begin(), w.x().end());
        EXPECT_EQ(x, coupling_points(scene, i.cut));
        EXPECT_EQ(w.speed(), i.kind().moving ? scene.speed : 0.0);
        if (i.kind().moving) {
          EXPECT_EQ(w.hertz_constant(), scene.hertz_constant);
        } else {
          EXPECT_GT(w.stiffness(), 0.0);
          EXPECT_GT(w.damping(), 0.0);
        }
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 2 * 6 + 2 * 3);  // both sides of one cut in six cases, of three in the last
}

ProtocolError interface_error(const wire::Interface& w) {
  try {
    from_wire(w);
  } catch (const ProtocolError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted interface " << w.ShortDebugString();
  return ProtocolError(wire::Error::CODE_UNSPECIFIED, "");
}

TEST(Conversions, AnInterfaceTheModelCannotHonourIsABadInterface) {
  const Scene scene = soil_scene();
  const auto parts = partition(scene, parse_case("ss-xx-jacobi"));
  const wire::Interface upper = to_wire(scene, parts[0].interfaces.at(0));  // sleepers above ss
  ASSERT_TRUE(upper.upper());

  // The upper side computes the ballast force itself: it cannot receive it.
  wire::Interface w = upper;
  w.clear_receives();
  w.add_receives(wire::FORCE);
  ProtocolError e = interface_error(w);
  EXPECT_EQ(e.code(), wire::Error::BAD_INTERFACE);
  EXPECT_NE(std::string(e.what()).find("'ss'"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("upper"), std::string::npos) << e.what();

  // Through a damped layer a displacement comes with its velocity.
  w = upper;
  w.clear_sends();
  w.add_sends(wire::DISPLACEMENT);
  EXPECT_EQ(interface_error(w).code(), wire::Error::BAD_INTERFACE);

  // The Hertz contact is undamped: no velocities cross it.
  w = to_wire(scene, partition(scene, parse_case("wr-xx-jacobi"))[1].interfaces.at(0));
  w.add_receives(wire::VELOCITY);
  e = interface_error(w);
  EXPECT_EQ(e.code(), wire::Error::BAD_INTERFACE);
  EXPECT_NE(std::string(e.what()).find("'wr'"), std::string::npos) << e.what();

  // A cut this model does not have.
  w = upper;
  w.set_cut("sg");
  e = interface_error(w);
  EXPECT_EQ(e.code(), wire::Error::BAD_INTERFACE);
  EXPECT_NE(std::string(e.what()).find("'sg'"), std::string::npos) << e.what();
}

}  // namespace protocol_test
}  // namespace railcosim
