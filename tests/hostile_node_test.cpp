// Node programs and the master against the bytes an attacker sends them:
// lock-step windows nested without end, scenes nested 100,000 levels deep
// (as a file and as a Configure's text), a waveform whose width asks for
// gigabytes. Each runs the real programs over real sockets and files: none
// may crash, grow past a bound or stay silent, and each refusal says what
// was wrong and where.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <fstream>

#include "connection.hpp"
#include "engine/coupled_statics.hpp"
#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

// A value of /proc/PID/status in KiB (VmHWM: the peak resident memory).
long status_kib(pid_t pid, const std::string& key) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  return -1;
}

// Whether the node process still runs (it is this process's child); when it
// has ended, how, for the failure message.
std::string ended(pid_t pid) {
  int st = 0;
  if (::waitpid(pid, &st, WNOHANG) != pid) return "";
  if (WIFSIGNALED(st)) return "killed by signal " + std::to_string(WTERMSIG(st));
  return "exited with status " + std::to_string(WEXITSTATUS(st));
}

// The participant `role` of wr-xx-jacobi on `scene`.
SubsystemConfig config_of(const Scene& scene, const std::string& role) {
  SubsystemConfig cfg;
  for (const ParticipantSpec& p : partition(scene, parse_case("wr-xx-jacobi")))
    if (p.role == role) cfg.participant = p;
  cfg.macro_step = scene.macro_step;
  cfg.tolerance = scene.tolerance;
  return cfg;
}

// Opens a configured and initialised session of `role` on `c`.
void open_session(Connection& c, const std::string& role) {
  const Scene scene = test::paper_scene();
  const SubsystemConfig cfg = config_of(scene, role);
  c.send(hello_envelope(role, scene_fingerprint(scene)));
  ASSERT_TRUE(c.receive(milliseconds(5000)).has_hello_reply());
  c.send(configure_envelope(scene, cfg));
  ASSERT_TRUE(c.receive(milliseconds(5000)).has_configured());
  wire::Envelope init;
  *init.mutable_initialize()->mutable_inputs() =
      to_wire(engine::zero_inputs(scene, cfg.participant));
  c.send(init);
  ASSERT_TRUE(c.receive(milliseconds(5000)).has_step_report());
}

// Waits until the node has closed the session on `c` (after an error reply).
void wait_closed(std::unique_ptr<Connection>& c) {
  try {
    while (true) c->receive(milliseconds(5000));
  } catch (const NetError&) {
  }
  c.reset();
}

// The node still serves: a new session gets its hello answered.
void expect_serving(const remote::LaunchedNode& node, const std::string& role) {
  ASSERT_EQ(ended(node.pid()), "");
  auto c = Connection::connect(node.address(), milliseconds(5000));
  c->send(hello_envelope(role, scene_fingerprint(test::paper_scene())));
  EXPECT_TRUE(c->receive(milliseconds(10000)).has_hello_reply());
}

wire::Envelope lockstep_window(std::uint64_t id) {
  wire::Envelope e;
  e.set_id(id);
  e.mutable_window()->set_first_step(0);
  e.mutable_window()->set_end_step(10);
  e.mutable_window()->set_lockstep(true);
  return e;
}

// A second lock-step Window inside a lock step is refused, naming it, and
// 20,000 of them (300 KB) do not crash the node (before, the request handler
// and the lock step called each other once per window: SIGSEGV after some
// 15,000).
TEST(HostileNode, NestedLockStepWindowsAreRefused) {
  remote::LaunchedNode node("vehicle_node", milliseconds(10000));
  {
    auto c = Connection::connect(node.address(), milliseconds(5000));
    open_session(*c, "vehicle");
    c->send(lockstep_window(7));
    EXPECT_TRUE(c->receive(milliseconds(5000)).has_ack());
    c->send(lockstep_window(8));
    const wire::Envelope r = c->receive(milliseconds(5000));
    ASSERT_TRUE(r.has_error()) << body_name(r);
    EXPECT_EQ(r.id(), 8u);
    EXPECT_EQ(r.error().code(), wire::Error::OUT_OF_ORDER);
    EXPECT_NE(r.error().message().find("a lock-step Window inside the lock step entered at "
                                       "macro step 0"),
              std::string::npos)
        << r.error().message();
    wait_closed(c);
  }
  {
    auto c = Connection::connect(node.address(), milliseconds(5000));
    open_session(*c, "vehicle");
    std::string flood;
    for (std::uint64_t k = 0; k < 20000; ++k) flood += encode_frame(lockstep_window(k + 1));
    try {
      c->send_raw(flood, milliseconds(5000));
    } catch (const NetError&) {
      // The node hung up after its error reply: what a refusal looks like.
    }
    wait_closed(c);
  }
  expect_serving(node, "vehicle");
}

// Texts nested 100,000 levels deep, each of the four ways TOML nests, put at
// line `line` of the paper scene.
std::vector<std::pair<std::string, std::string>> deep_texts(int line) {
  const int depth = 100000;
  std::string dotted = "a", header = "[a", array = "x = ", inline_table = "y = ";
  for (int k = 1; k < depth; ++k) dotted += ".a", header += ".a";
  dotted += " = 1\n";
  header += "]\n";
  array += std::string(depth, '[') + std::string(depth, ']') + "\n";
  for (int k = 0; k < depth; ++k) inline_table += "{z = ";
  inline_table += "1" + std::string(depth, '}') + "\n";
  const std::string paper = test::read_file(test::source_path("scenes/paper.toml"));
  std::size_t at = 0;
  for (int k = 1; k < line; ++k) at = paper.find('\n', at) + 1;
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [name, text] :
       {std::pair{"dotted key", dotted}, std::pair{"header", header}, std::pair{"array", array},
        std::pair{"inline table", inline_table}})
    out.emplace_back(name, paper.substr(0, at) + text + paper.substr(at));
  return out;
}

// The master reads such a scene file, even under --check, and refuses it
// naming the file and the line (before, a dotted key or a header 100,000
// deep crashed it with SIGSEGV).
TEST(HostileNode, DeeplyNestedSceneFilesAreRefusedByTheMaster) {
  const fs::path dir = test::temp_dir("deep_scene");
  for (const auto& [name, text] : deep_texts(3)) {
    SCOPED_TRACE(name);
    const fs::path file = dir / "deep.toml";
    std::ofstream(file) << text;
    const test::Outcome o =
        test::run_master("run --check --scene " + file.string() + " --case wr-xx-jacobi");
    EXPECT_EQ(o.status, 2) << o.output.substr(0, 2000);  // a scene error
    EXPECT_NE(o.output.find(file.string() + ":3: "), std::string::npos) << o.output.substr(0, 2000);
    EXPECT_NE(o.output.find("levels deep or more; at most 32"), std::string::npos)
        << o.output.substr(0, 2000);
  }
  fs::remove_all(dir);
}

// The same texts as a Configure's scene: the node refuses them (BAD_SCENE,
// naming the line) and serves on (before, the node crashed).
TEST(HostileNode, DeeplyNestedConfigureScenesAreRefusedByANode) {
  remote::LaunchedNode node("vehicle_node", milliseconds(10000));
  const Scene scene = test::paper_scene();
  for (const auto& [name, text] : deep_texts(5)) {
    SCOPED_TRACE(name);
    auto c = Connection::connect(node.address(), milliseconds(5000));
    c->send(hello_envelope("vehicle", scene_fingerprint(scene)));
    ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
    wire::Envelope e = configure_envelope(scene, config_of(scene, "vehicle"));
    e.mutable_configure()->set_scene(text);
    c->send(e);
    const wire::Envelope r = c->receive(milliseconds(10000));
    ASSERT_TRUE(r.has_error()) << body_name(r);
    EXPECT_EQ(r.error().code(), wire::Error::BAD_SCENE);
    EXPECT_NE(r.error().message().find(":5: "), std::string::npos) << r.error().message();
    EXPECT_NE(r.error().message().find("levels deep or more; at most 32"), std::string::npos)
        << r.error().message();
    wait_closed(c);
  }
  expect_serving(node, "vehicle");
}

// A 17-byte SetInputs whose waveform says 2^27 values per sample and has no
// sample: refused, naming the width the participant takes, before anything
// is allocated. The node's peak resident memory stays under 256 MiB (before,
// it allocated and zeroed 1 GiB, then refused).
TEST(HostileNode, AWaveformWidthFromTheWireAllocatesNothing) {
  remote::LaunchedNode node("vehicle_node", milliseconds(10000));
  auto c = Connection::connect(node.address(), milliseconds(5000));
  open_session(*c, "vehicle");
  for (const bool in_step : {false, true}) {
    SCOPED_TRACE(in_step ? "in a step" : "in set_inputs");
    wire::Envelope e;  // id 0: the 17 bytes of the attack
    wire::InputWaveforms* w = nullptr;
    if (in_step) {
      e.mutable_step()->set_step(0);
      e.mutable_step()->set_h(test::paper_scene().macro_step);
      w = e.mutable_step()->mutable_waveforms();
    } else {
      e.mutable_set_inputs()->set_step(0);
      w = e.mutable_set_inputs()->mutable_waveforms();
    }
    w->add_interfaces()->set_width(1u << 27);
    if (!in_step) {
      EXPECT_LE(encode_frame(e).size(), 17u);
    }
    c->send(e);
    const wire::Envelope r = c->receive(milliseconds(10000));
    ASSERT_TRUE(r.has_error()) << body_name(r);
    EXPECT_EQ(r.error().code(), wire::Error::BAD_REQUEST);
    EXPECT_NE(r.error().message().find("has width 134217728; participant vehicle takes 1 values"),
              std::string::npos)
        << r.error().message();
    const long peak = status_kib(node.pid(), "VmHWM");
    ASSERT_GT(peak, 0);
    EXPECT_LT(peak, 256 * 1024) << "KiB of peak resident memory";
    wait_closed(c);
    if (!in_step) {
      c = Connection::connect(node.address(), milliseconds(5000));
      open_session(*c, "vehicle");
    }
  }
  expect_serving(node, "vehicle");
}

}  // namespace
}  // namespace railcosim
