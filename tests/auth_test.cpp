// Who may connect: the hash functions against their published vectors, and
// nodes that require a shared secret, driven over real sockets.
#include "auth.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "engine/coupled_statics.hpp"
#include "remote/remote_participant.hpp"
#include "server.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using std::chrono::milliseconds;

constexpr const char* kSecret = "correct horse battery staple";

std::string hex(const Digest& d) {
  std::string s;
  char buf[3];
  for (auto b : d) {
    std::snprintf(buf, sizeof buf, "%02x", b);
    s += buf;
  }
  return s;
}

TEST(Sha256, PublishedVectors) {
  EXPECT_EQ(hex(sha256("")), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(hex(sha256("abc")), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(hex(sha256("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(hex(sha256(std::string(1000000, 'a'))),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(HmacSha256, Rfc4231Vectors) {
  EXPECT_EQ(hex(hmac_sha256(std::string(20, '\x0b'), "Hi There")),
            "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7");
  EXPECT_EQ(hex(hmac_sha256("Jefe", "what do ya want for nothing?")),
            "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
  EXPECT_EQ(hex(hmac_sha256(std::string(131, '\xaa'),
                            "Test Using Larger Than Block-Size Key - Hash Key First")),
            "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54");
}

TEST(Auth, NoncesAreFreshAndAnswersDependOnEverything) {
  const std::string a = random_nonce(), b = random_nonce();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_NE(a, b);
  const std::string s = "a secret of enough length";
  EXPECT_NE(auth_answer(s, "track", a), auth_answer(s, "track", b));
  EXPECT_NE(auth_answer(s, "track", a), auth_answer(s, "soil", a));
  EXPECT_NE(auth_answer(s + "!", "track", a), auth_answer(s, "track", a));
  // The zero byte ends the participant's name: it cannot run into the nonce.
  EXPECT_NE(auth_answer(s, "soil", "x" + a), auth_answer(s, "soilx", a));
  EXPECT_TRUE(constant_time_equal(auth_answer(s, "track", a), auth_answer(s, "track", a)));
}

// The answer as docs/protocol.md defines it, HMAC-SHA256(secret,
// "railcosim-auth-v2" | participant | 0 | nonce); the expected values come
// from another implementation (Python's hmac module), for outside
// participants to check theirs against.
TEST(Auth, AnswerMatchesTheDocumentedConstruction) {
  std::string nonce;
  for (int i = 0; i < 32; ++i) nonce += static_cast<char>(i);  // 00 01 ... 1f
  auto hex_of = [](const std::string& raw) {
    Digest d{};
    std::copy(raw.begin(), raw.end(), d.begin());
    return hex(d);
  };
  EXPECT_EQ(hex_of(auth_answer(kSecret, "soil", nonce)),
            "4e2d5487f0cf7d11491de7fa96b114c303c3bc603281743421002ef021887e49");
  EXPECT_EQ(hex_of(auth_answer(kSecret, "vehicle", nonce)),
            "eaf9b6376227518e8a6a3abf3ff764c63a8c293b9aa0cb6ea0183ec8723e4f89");
}

class TokenNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    NodeOptions o;
    o.role = "vehicle";
    o.token = kSecret;
    server_ = std::make_unique<NodeServer>(o, Address{"127.0.0.1", 0});
    thread_ = std::thread([this] { server_->run(false); });
    scene_ = test::paper_scene();
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
  }
  // The vehicle of the paper's wr-xx-jacobi case.
  SubsystemConfig config() const {
    SubsystemConfig cfg;
    cfg.participant = partition(scene_, parse_case("wr-xx-jacobi")).front();
    cfg.macro_step = scene_.macro_step;
    cfg.tolerance = scene_.tolerance;
    return cfg;
  }
  // Sends a hello, returns the challenge's nonce.
  std::string hello(Connection& c) {
    c.send(hello_envelope("vehicle", scene_fingerprint(scene_)));
    const wire::Envelope r = c.receive(milliseconds(5000));
    EXPECT_TRUE(r.has_challenge()) << body_name(r);
    return r.challenge().nonce();
  }
  void expect_refused(Connection& c) {
    const wire::Envelope r = c.receive(milliseconds(5000));
    ASSERT_TRUE(r.has_error()) << body_name(r);
    EXPECT_EQ(r.error().code(), wire::Error::UNAUTHORIZED);
    EXPECT_THROW(c.receive(milliseconds(5000)), NetError);  // and nothing more
  }

  std::unique_ptr<NodeServer> server_;
  std::thread thread_;
  Scene scene_;
};

TEST_F(TokenNodeTest, TheRightSecretOpensASession) {
  remote::RemoteParticipant p(server_->local_address(), scene_, config(), {}, std::string(kSecret));
  ASSERT_EQ(config().participant.role, "vehicle");
  Subsystem local(scene_, config());
  const CouplingData in = engine::zero_inputs(scene_, config().participant);
  const StepResult remote = p.initialize(in);
  ASSERT_EQ(remote.outputs.size(), 1u);  // the wr interface
  EXPECT_EQ(remote.outputs[0].displacement.size(), 1u);
  EXPECT_EQ(remote.outputs, local.initialize(in).outputs);
}

TEST_F(TokenNodeTest, AWrongSecretGetsOnlyARefusal) {
  auto c = Connection::connect(server_->local_address(), milliseconds(5000));
  const std::string nonce = hello(*c);
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(auth_answer("not the right secret!", "vehicle", nonce));
  c->send(auth);
  expect_refused(*c);
}

TEST_F(TokenNodeTest, AnAnswerForAnotherParticipantGetsOnlyARefusal) {
  auto c = Connection::connect(server_->local_address(), milliseconds(5000));
  const std::string nonce = hello(*c);
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(auth_answer(kSecret, "track", nonce));  // the hello said vehicle
  c->send(auth);
  expect_refused(*c);
}

TEST_F(TokenNodeTest, NoAnswerGetsOnlyARefusal) {
  auto c = Connection::connect(server_->local_address(), milliseconds(5000));
  hello(*c);
  wire::Envelope init;
  init.mutable_initialize();  // skipping the answer
  c->send(init);
  expect_refused(*c);
}

TEST_F(TokenNodeTest, ReplayingAnOldAnswerFails) {
  auto c1 = Connection::connect(server_->local_address(), milliseconds(5000));
  const std::string nonce = hello(*c1);
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(auth_answer(kSecret, "vehicle", nonce));
  c1->send(auth);
  ASSERT_TRUE(c1->receive(milliseconds(5000)).has_hello_reply());
  wire::Envelope bye;
  bye.mutable_shutdown();
  c1->send(bye);
  c1->receive(milliseconds(5000));
  // A second session gets a new nonce: the recorded answer does not open it.
  auto c2 = Connection::connect(server_->local_address(), milliseconds(5000));
  hello(*c2);
  c2->send(auth);
  expect_refused(*c2);
}

TEST_F(TokenNodeTest, AMasterWithoutTheSecretIsToldWhatToPass) {
  try {
    remote::RemoteParticipant p(server_->local_address(), scene_, config());
    FAIL() << "opened a session without the secret";
  } catch (const remote::NodeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("--token-file"), std::string::npos) << e.what();
  }
}

TEST(TokenNodeProgram, RefusesANonLoopbackAddressWithoutAToken) {
  const std::string cmd = std::string(RAILCOSIM_BIN_DIR) + "/track_node --listen 0.0.0.0:0 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  std::array<char, 512> buf{};
  while (fgets(buf.data(), buf.size(), p)) out += buf.data();
  const int st = pclose(p);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) != 0);
  EXPECT_NE(out.find("refusing to listen on 0.0.0.0:0 without --token-file"), std::string::npos)
      << out;
}

TEST(TokenFile, ShortSecretsAreRefused) {
  const auto path = std::filesystem::temp_directory_path() / "railcosim_short.token";
  std::ofstream(path) << "short\n";
  std::filesystem::permissions(
      path, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  EXPECT_THROW(read_token_file(path.string()), std::runtime_error);
  std::ofstream(path) << "  a long enough secret, really  \n";
  EXPECT_EQ(read_token_file(path.string()), "a long enough secret, really");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace railcosim
