#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"
#include "wire.hpp"

namespace railcosim {
namespace {

wire::Envelope sample_step_report() {
  StepResult r;
  r.outputs.displacement = {1.5e-3, -2.25e-4, 0.1 + 0.2};  // values that print inexactly
  r.outputs.velocity = {0.0, -0.0, 1e-300};
  r.max_abs_displacement = 1.9e-3;
  r.finite = true;
  r.row = HistoryRow{0.0123, 1.97e-3, 110362.5};
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
  EXPECT_EQ(r.outputs.displacement, (std::vector<double>{1.5e-3, -2.25e-4, 0.1 + 0.2}));
  EXPECT_TRUE(std::signbit(r.outputs.velocity[1]));
  EXPECT_EQ(r.outputs.velocity[2], 1e-300);
  EXPECT_TRUE(r.outputs.force.empty());
  ASSERT_TRUE(r.row.has_value());
  EXPECT_EQ(r.row->contact_force, 110362.5);
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

TEST(Conversions, MixedCouplingPointsAreRejected) {
  wire::CouplingData w;
  w.add_points()->set_displacement(1.0);
  w.add_points()->set_force(2.0);
  EXPECT_THROW(from_wire(w), ProtocolError);
}

TEST(Conversions, SceneRoundTripsAndItsFingerprintSeesEveryChange) {
  const Scene s = test::paper_scene();
  const Scene back = from_wire(to_wire(s), "wire");
  EXPECT_EQ(scene_fingerprint(back), scene_fingerprint(s));
  EXPECT_EQ(back.hertz_constant, s.hertz_constant);
  EXPECT_EQ(back.speed, s.speed);
  Scene changed = s;
  changed.pad_damping = std::nextafter(s.pad_damping, 1e9);
  EXPECT_NE(scene_fingerprint(changed), scene_fingerprint(s));
}

TEST(Conversions, AnInvalidSceneOnTheWireIsABadScene) {
  Scene s = test::paper_scene();
  s.sleeper_mass = -1.0;
  try {
    from_wire(to_wire(s), "the master's scene");
    FAIL() << "no error";
  } catch (const ProtocolError& e) {
    EXPECT_EQ(e.code(), wire::Error::BAD_SCENE);
    EXPECT_NE(std::string(e.what()).find("sleepers.mass"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace railcosim
