// The shared secret authenticates both ends. A master run with --token-file
// against nodes started without one, and against an impostor at a node's
// address that challenges the master and then takes any answer (it cannot
// know the secret), refuses before it sends the scene, naming the node's
// role and address; nodes that hold the secret run the case.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>

#include "auth.hpp"
#include "fake_node.hpp"
#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

constexpr const char* kCase = "wr-xx-jacobi";

std::string token_file(const fs::path& dir) {
  const fs::path p = dir / "token";
  std::ofstream(p) << "the secret of the nodes this master trusts\n";
  ::chmod(p.c_str(), 0600);
  return p.string();
}

test::Outcome run_with(const std::string& token, const Address& vehicle, const Address& track,
                       const fs::path& out) {
  return test::run_master("run --scene " + test::source_path("scenes/paper.toml") + " --case " +
                          kCase + " --node vehicle=" + vehicle.str() + " --node track=" +
                          track.str() + " --token-file " + token + " --out " + out.string());
}

TEST(MutualAuth, AMasterWithASecretRefusesNodesWithout) {
  const fs::path dir = test::temp_dir("mutual_none");
  remote::LaunchedNode vehicle("vehicle_node", milliseconds(10000));
  remote::LaunchedNode track("track_node", milliseconds(10000));
  const test::Outcome o = run_with(token_file(dir), vehicle.address(), track.address(), dir);
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("vehicle node at " + vehicle.address().str() +
                          ": it asked no challenge, so it cannot prove that it holds the shared "
                          "secret of --token-file"),
            std::string::npos)
      << o.output;
  fs::remove_all(dir);
}

// An impostor at the vehicle's address: it challenges the master, takes its
// answer and says hello back, with `proof` (it cannot compute the right one).
void expect_impostor_refused(const std::string& proof, const std::string& expected) {
  const fs::path dir = test::temp_dir("mutual_impostor");
  const std::string token = token_file(dir);
  std::atomic<bool> configured{false};
  test::FakeNode impostor("vehicle", [&](const wire::Envelope& request, wire::Envelope& reply) {
    configured = configured || request.has_configure();
    if (request.has_hello()) {
      reply.Clear();
      reply.set_id(request.id());
      reply.mutable_challenge()->set_nonce(random_nonce());
    } else if (request.has_auth()) {
      reply.Clear();
      reply.set_id(request.id());
      auto* r = reply.mutable_hello_reply();
      r->set_protocol_version(kProtocolVersion);
      r->set_participant("vehicle");
      r->set_proof(proof);
    }
    return false;
  });
  remote::LaunchedNode track("track_node", milliseconds(10000), "127.0.0.1:0", "", token);
  const test::Outcome o = run_with(token, impostor.address(), track.address(), dir);
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("vehicle node at " + impostor.address().str() + ": " + expected),
            std::string::npos)
      << o.output;
  EXPECT_FALSE(configured) << "the impostor was sent the scene";
  fs::remove_all(dir);
}

TEST(MutualAuth, AnImpostorWithoutAProofIsRefused) {
  expect_impostor_refused(
      "",
      "it did not prove that it holds the shared secret of --token-file (its proof was missing)");
}

TEST(MutualAuth, AnImpostorWithAForgedProofIsRefused) {
  expect_impostor_refused(
      random_nonce(),
      "it did not prove that it holds the shared secret of --token-file (its proof was wrong)");
}

TEST(MutualAuth, NodesWithTheSecretRunTheCase) {
  const fs::path dir = test::temp_dir("mutual_both");
  const std::string token = token_file(dir);
  remote::LaunchedNode vehicle("vehicle_node", milliseconds(10000), "127.0.0.1:0", "", token);
  remote::LaunchedNode track("track_node", milliseconds(10000), "127.0.0.1:0", "", token);
  const test::Outcome o = run_with(token, vehicle.address(), track.address(), dir);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(test::read_file(dir / kCase / "summary.json").find("\"status\": \"ok\""),
            std::string::npos);
  fs::remove_all(dir);
}

// The documented construction of the node's proof, for outside participants
// to check theirs against (the value from Python's hmac module).
TEST(MutualAuth, ProofMatchesTheDocumentedConstruction) {
  std::string hello_nonce, challenge;
  for (int i = 0; i < 32; ++i) {
    hello_nonce += static_cast<char>(i);       // 00 01 ... 1f
    challenge += static_cast<char>(0x20 + i);  // 20 21 ... 3f
  }
  const std::string p = auth_proof("correct horse battery staple", "soil", hello_nonce, challenge);
  std::string hex;
  char buf[3];
  for (unsigned char b : p) {
    std::snprintf(buf, sizeof buf, "%02x", b);
    hex += buf;
  }
  EXPECT_EQ(hex, "aff466879993f445baf31dec6f67df7ba9dde0581198ed31b13825d48a66b99f");
}

}  // namespace
}  // namespace railcosim
