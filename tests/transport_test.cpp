// The table of transports: their names as users give them, what a name
// says (remote or not), the other transport of a study's stage 2, and the
// errors that name an unknown one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "remote/transport.hpp"
#include "study/study_plan.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using remote::find_transport;
using remote::is_remote_transport;
using remote::make_transport;
using remote::NodePool;
using remote::other_transport;
using remote::parse_transport;
using remote::SceneTransport;
using remote::tcp_transport;
using remote::Transport;
using remote::transport_names;

TEST(TransportTable, NamesTheTransportsUsersGive) {
  EXPECT_EQ(transport_names(), (std::vector<std::string>{"inproc", "tcp"}));
  for (const std::string& name : transport_names()) {
    const Transport* t = find_transport(name);
    ASSERT_NE(t, nullptr) << name;
    EXPECT_EQ(std::string(t->name()), name);
    EXPECT_TRUE(t->carries_waveforms()) << name;
  }
  EXPECT_EQ(find_transport("carrier-pigeon"), nullptr);
}

TEST(TransportTable, SaysWhichTransportsAreRemote) {
  EXPECT_FALSE(is_remote_transport("inproc"));
  EXPECT_TRUE(is_remote_transport("tcp"));
  EXPECT_FALSE(is_remote_transport("carrier-pigeon"));
  EXPECT_EQ(other_transport("tcp"), "inproc");
  EXPECT_EQ(other_transport("inproc"), "tcp");
}

TEST(TransportTable, AnUnknownNameIsAnErrorNamingTheKnownOnes) {
  try {
    parse_transport("udp", "--transport");
    FAIL() << "accepted transport udp";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "--transport: unknown transport 'udp' (inproc or tcp)");
  }
}

TEST(TransportTable, MakesTheParticipantsOfAScene) {
  const Scene scene = test::paper_scene();
  const SceneTransport local = make_transport(parse_transport("inproc", "--transport"), scene);
  EXPECT_EQ(local.name, "inproc");
  EXPECT_TRUE(static_cast<bool>(local.factory));
  // Over TCP the nodes come from a pool the caller keeps.
  try {
    make_transport(parse_transport("tcp", "--transport"), scene);
    FAIL() << "a tcp transport without a node pool";
  } catch (const std::logic_error& e) {
    EXPECT_EQ(std::string(e.what()), "the tcp transport needs a node pool");
  }
  NodePool pool;
  EXPECT_EQ(tcp_transport(scene, {}, pool).name, "tcp");
}

TEST(TransportTable, AStudyPlanNamingNoTransportIsRefusedWithItsLine) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "railcosim_transport_test_plan.txt";
  {
    std::ofstream out(file);
    out << "#% format = " << study::kPlanFormat << "\n#% transport = udp\n";
  }
  try {
    study::read_plan(file);
    FAIL() << "read a plan over transport udp";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ":2: transport: unknown transport 'udp' (inproc or tcp)");
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace railcosim
