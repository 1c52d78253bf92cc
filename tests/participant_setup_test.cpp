// What a participant built by NodeOptions::configure is told at Configure:
// its interfaces as the master sent them (the scene is not read), the run's
// settings, its own configuration (the table of --config, else the master's
// Configure.own_config), and how its refusals reach the master
// (BadRequestError: BAD_REQUEST; BadInterfaceError, std::invalid_argument:
// BAD_INTERFACE). A real node session, driven by the master's own messages.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "cosim_case.hpp"
#include "session.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace participant_setup_test {
namespace {

// A participant that only declares its outputs: these tests end at Configure.
class Declared final : public Participant {
 public:
  std::string name() const override { return "declared"; }
  Channels channels() const override { return {{"soil_peak_m"}, {"soil_m"}}; }
  CouplingData statics(const CouplingData&) override { return {}; }
  StepResult initialize(const CouplingData&) override { return {}; }
  void set_inputs(long, const CouplingData&) override {}
  CouplingData outputs() override { return {}; }
  void start_step(long) override {}
  StepResult finish_step() override { return {}; }
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {}; }
  void restore(const ParticipantState&) override {}
};

// The soil's part of a case, as the master configures it.
SubsystemConfig soil_config(const Scene& scene, const char* case_name) {
  SubsystemConfig c;
  c.participant = partition(scene, parse_case(case_name)).back();
  c.macro_step = scene.macro_step;
  c.tolerance = scene.tolerance;
  return c;
}

class ParticipantSetupTest : public ::testing::Test {
 protected:
  ParticipantSetupTest()
      : scene_(load_scene(test::source_path("scenes/soil.toml"))),
        conf_(configure_envelope(scene_, soil_config(scene_, "ss-xx-jacobi"))) {
    options_.role = "soil";
    options_.configure = [this](const ParticipantSetup& s) -> std::unique_ptr<Participant> {
      setup_ = s;
      if (refuse_) refuse_(s);
      return std::make_unique<Declared>();
    };
  }

  // Hello and `conf_` to a fresh session: the reply to Configure.
  wire::Envelope configure() {
    NodeSession session(options_);
    bool close = false;
    const wire::Envelope hello = session.handle(hello_envelope("soil", 42), close);
    EXPECT_TRUE(hello.has_hello_reply()) << hello.ShortDebugString();
    return session.handle(conf_, close);
  }
  std::string refused(wire::Error::Code code) {
    const wire::Envelope r = configure();
    EXPECT_TRUE(r.has_error()) << r.ShortDebugString();
    EXPECT_EQ(wire::Error::Code_Name(r.error().code()), wire::Error::Code_Name(code));
    return r.error().message();
  }

  Scene scene_;
  wire::Envelope conf_;
  NodeOptions options_;
  ParticipantSetup setup_;
  std::function<void(const ParticipantSetup&)> refuse_;
};

TEST_F(ParticipantSetupTest, TheInterfacesAreThoseTheMasterSentAndTheSceneIsNotRead) {
  wire::Configure& c = *conf_.mutable_configure();
  c.set_scene("this is [[ not a scene");  // the product's model would answer BAD_SCENE
  c.mutable_interfaces(0)->set_x(2, 1234.5);
  ASSERT_TRUE(configure().has_configured());
  EXPECT_EQ(setup_.participant, "soil");
  ASSERT_EQ(setup_.interfaces.size(), 1u);
  const Interface& i = setup_.interfaces[0];
  const wire::Interface& w = c.interfaces(0);
  EXPECT_EQ(i.cut, "ss");
  EXPECT_EQ(i.peer, "vehicle");  // ss-xx-jacobi: everything above the cut
  EXPECT_FALSE(i.upper);
  ASSERT_EQ(i.n(), static_cast<std::size_t>(scene_.sleeper_count));
  for (int k = 0; k < w.x_size(); ++k) EXPECT_EQ(i.x[static_cast<std::size_t>(k)], w.x(k));
  EXPECT_EQ(i.x[2], 1234.5);
  EXPECT_EQ(i.receives, (std::vector<Quantity>{Quantity::kDisplacement, Quantity::kVelocity}));
  EXPECT_EQ(i.sends, (std::vector<Quantity>{Quantity::kDisplacement, Quantity::kVelocity}));
  EXPECT_FALSE(i.receives_force());
  EXPECT_EQ(i.stiffness, scene_.ballast_stiffness);
  EXPECT_EQ(i.damping, scene_.ballast_damping);
  EXPECT_EQ(i.hertz_constant, 0.0);
  EXPECT_EQ(i.speed, 0.0);
  ASSERT_EQ(i.footprints.size(), i.n());
  const Footprint f = footprints(scene_, find_cut("ss")).at(5);
  EXPECT_EQ(i.footprints[5].x, f.x);
  EXPECT_EQ(i.footprints[5].y, f.y);
  EXPECT_EQ(i.footprints[5].length, f.length);
  EXPECT_EQ(i.footprints[5].width, f.width);
  EXPECT_EQ(i.describe(), "ss (lower side, " + std::to_string(i.n()) + " points)");
  EXPECT_EQ(setup_.run.macro_step, scene_.macro_step);
  EXPECT_EQ(setup_.run.end_time, scene_.end_time);
  EXPECT_EQ(setup_.run.tolerance, scene_.tolerance);
  EXPECT_EQ(setup_.run.micro_steps, 0);
  EXPECT_EQ(setup_.run.max_micro_steps, options_.max_micro_steps);
  EXPECT_FALSE(setup_.run.carry_acceleration);
  EXPECT_TRUE(setup_.config.empty());  // a built-in soil's scene sends no table
}

TEST_F(ParticipantSetupTest, ItsConfigurationIsTheMastersTableUnlessConfigNamesAFile) {
  conf_.mutable_configure()->set_own_config("mass = 700.5\nlayers = [1, 2.5]\nname = \"clay\"\n");
  ASSERT_TRUE(configure().has_configured());
  EXPECT_EQ(setup_.config.source(), "the master's scene");
  EXPECT_EQ(setup_.config.number("mass"), 700.5);
  EXPECT_EQ(setup_.config.numbers("layers"), (std::vector<double>{1.0, 2.5}));
  EXPECT_EQ(setup_.config.string("name"), "clay");
  EXPECT_EQ(setup_.config.keys(), (std::vector<std::string>{"layers", "mass", "name"}));
  EXPECT_EQ(setup_.config.number("depth", 3.25), 3.25);

  options_.config_file = ConfigFile{"own.toml", "[soil]\nmass = 1.5\n[ground]\nmass = 2\n", ""};
  ASSERT_TRUE(configure().has_configured());
  EXPECT_EQ(setup_.config.source(), "own.toml");
  EXPECT_EQ(setup_.config.number("mass"), 1.5);
  options_.config_file->table = "ground";
  ASSERT_TRUE(configure().has_configured());
  EXPECT_EQ(setup_.config.number("mass"), 2.0);
  EXPECT_EQ(setup_.config.integer("mass"), 2);
}

TEST_F(ParticipantSetupTest, ABadConfigurationIsABadRequestNamingTheFileAndTheKey) {
  options_.config_file = ConfigFile{"own.toml", "[soil]\nmass = \"heavy\"\n", ""};
  refuse_ = [](const ParticipantSetup& s) { (void)s.config.number("stiffness"); };
  EXPECT_EQ(refused(wire::Error::BAD_REQUEST),
            "participant soil: own.toml: key 'soil.stiffness': missing");
  refuse_ = [](const ParticipantSetup& s) { (void)s.config.number("mass"); };
  EXPECT_EQ(refused(wire::Error::BAD_REQUEST),
            "participant soil: own.toml: key 'soil.mass': expected a number");
  options_.config_file->text = "[soil]\nmass = \n";
  EXPECT_NE(refused(wire::Error::BAD_REQUEST).find("own.toml: line 2"), std::string::npos);
  options_.config_file->text = "[ground]\nmass = 1\n";
  EXPECT_NE(refused(wire::Error::BAD_REQUEST).find("own.toml: no [soil] table"), std::string::npos);
  options_.config_file.reset();
  refuse_ = [](const ParticipantSetup& s) { (void)s.config.number("mass"); };
  EXPECT_EQ(refused(wire::Error::BAD_REQUEST),
            "participant soil: no --config FILE, and the master's scene sends no [soil] table: "
            "key 'soil.mass': missing");
  refuse_ = [](const ParticipantSetup&) { throw BadRequestError("set simulation.micro_steps"); };
  EXPECT_EQ(refused(wire::Error::BAD_REQUEST), "participant soil: set simulation.micro_steps");
}

TEST_F(ParticipantSetupTest, AnInterfaceItCannotHonourIsABadInterface) {
  refuse_ = [](const ParticipantSetup& s) {
    throw BadInterfaceError("cannot serve " + s.interfaces[0].describe());
  };
  EXPECT_NE(refused(wire::Error::BAD_INTERFACE).find("participant soil: cannot serve ss"),
            std::string::npos);
  refuse_ = [](const ParticipantSetup&) { throw std::invalid_argument("not this cut"); };
  EXPECT_EQ(refused(wire::Error::BAD_INTERFACE), "participant soil: not this cut");
}

TEST_F(ParticipantSetupTest, AQuantityOutsideTheProtocolIsABadRequest) {
  conf_.mutable_configure()->mutable_interfaces(0)->set_receives(0, static_cast<wire::Quantity>(7));
  EXPECT_EQ(refused(wire::Error::BAD_REQUEST),
            "configure: interface 0 (ss) receives: quantity 7 is none of DISPLACEMENT, VELOCITY, "
            "FORCE");
}

}  // namespace
}  // namespace participant_setup_test
}  // namespace railcosim
