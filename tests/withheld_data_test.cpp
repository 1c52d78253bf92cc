// The direct plane against a vehicle node that withholds its peer data from
// the track from macro step 20 on (a proxy in front of the real track node
// drops the vehicle's PeerData on their link) while it goes on reporting
// steps it never took: alone, with progress frames, with a forged claim to
// wait for the track. The honest track waits and says so; the master must
// name the vehicle (it named the track: "it says it waits for the vehicle
// participant, whose step reports reached macro step 200", and with
// progress frames "step budget exhausted" for the track, which sent none).
#include <gtest/gtest.h>
#include <sys/socket.h>

#include <list>
#include <mutex>
#include <thread>

#include "fake_node.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using std::chrono::milliseconds;
namespace asio = boost::asio;
using asio::ip::tcp;

constexpr long kWithheldFrom = 20;  // the first point whose data are dropped
constexpr long kSteps = 200;

// Forwards every connection to `to`; on a peer link (its first frame a
// Hello of role "peer") drops the PeerData from the connecting end for
// points from kWithheldFrom on.
class WithholdingProxy {
 public:
  explicit WithholdingProxy(Address to) : to_(std::move(to)), acceptor_(io_) {
    acceptor_.open(tcp::v4());
    acceptor_.bind({asio::ip::make_address("127.0.0.1"), 0});
    acceptor_.listen();
    threads_.emplace_back([this] { serve(); });
  }
  ~WithholdingProxy() {
    ::shutdown(acceptor_.native_handle(), SHUT_RDWR);
    threads_.front().join();  // it takes no connection any more
    for (tcp::socket& s : sockets_) ::shutdown(s.native_handle(), SHUT_RDWR);
    for (auto t = std::next(threads_.begin()); t != threads_.end(); ++t) t->join();
  }
  Address address() const { return {"127.0.0.1", acceptor_.local_endpoint().port()}; }

 private:
  void serve() {
    while (true) {
      tcp::socket in(io_);
      boost::system::error_code ec;
      acceptor_.accept(in, ec);
      if (ec) return;
      tcp::socket out(io_);
      out.connect({asio::ip::make_address(to_.host), to_.port}, ec);
      if (ec) return;
      std::lock_guard<std::mutex> lock(mutex_);
      sockets_.push_back(std::move(in));
      tcp::socket& a = sockets_.back();
      sockets_.push_back(std::move(out));
      tcp::socket& b = sockets_.back();
      threads_.emplace_back([&a, &b] { filter(a, b); });
      threads_.emplace_back([&a, &b] { copy(b, a); });
    }
  }
  static void copy(tcp::socket& from, tcp::socket& to) {
    std::array<char, 65536> buf{};
    boost::system::error_code ec;
    while (true) {
      const std::size_t n = from.read_some(asio::buffer(buf), ec);
      if (ec || !asio::write(to, asio::buffer(buf.data(), n), ec) || ec) break;
    }
    ::shutdown(to.native_handle(), SHUT_WR);
  }
  static void filter(tcp::socket& from, tcp::socket& to) {
    FrameDecoder decoder;
    std::array<char, 65536> buf{};
    boost::system::error_code ec;
    bool first = true, peer = false;
    while (true) {
      const std::size_t n = from.read_some(asio::buffer(buf), ec);
      if (ec) break;
      decoder.feed(buf.data(), n);
      wire::Envelope e;
      while (decoder.next(e) == FrameDecoder::Status::kFrame) {
        if (first) peer = e.has_hello() && e.hello().role() == "peer";
        first = false;
        if (peer && e.has_peer_data() && e.peer_data().point() >= kWithheldFrom) continue;
        const std::string f = encode_frame(e);
        asio::write(to, asio::buffer(f), ec);
      }
    }
    ::shutdown(to.native_handle(), SHUT_WR);
  }

  Address to_;
  asio::io_context io_;
  tcp::acceptor acceptor_;
  std::mutex mutex_;
  std::list<tcp::socket> sockets_;
  std::list<std::thread> threads_;
};

bool nap(milliseconds t, const std::atomic<bool>& stop) {
  for (auto slept = milliseconds(0); slept < t; slept += milliseconds(10)) {
    if (stop) return false;
    std::this_thread::sleep_for(milliseconds(10));
  }
  return !stop;
}

void send_envelope(int fd, const wire::Envelope& e) {
  const std::string f = encode_frame(e);
  (void)::send(fd, f.data(), f.size(), MSG_NOSIGNAL);
}

struct Lies {
  bool progress = false;  // progress frames for the step after its forged reports
  bool claim = false;     // says it waits for the track
  bool forge = true;      // false: its reports stop where the track's do (a tie)
};

// The vehicle's report stream: passed on up to macro step kWithheldFrom,
// then reports forged up to the window's end (the session itself stalls),
// then what `lies` says, until the run ends.
test::FakeNode::Reports lying_reports(Lies lies) {
  return [lies](int fd, const std::string& frame, const std::atomic<bool>& stop) {
    wire::Envelope e;
    e.ParseFromArray(frame.data() + 4, static_cast<int>(frame.size() - 4));
    // The liar does not say it waits (the claim rides with its reports).
    e.mutable_reports()->clear_waiting_for();
    if (e.reports().reports_size() == 0) return;
    send_envelope(fd, e);
    wire::StepReport last = e.reports().reports(e.reports().reports_size() - 1);
    if (last.step() < kWithheldFrom) return;
    const double h = last.t() / static_cast<double>(last.step());
    while (lies.forge && last.step() < kSteps - 1 && nap(milliseconds(10), stop)) {
      wire::Envelope forged;
      forged.set_id(e.id());
      for (int k = 0; k < 20 && last.step() < kSteps - 1; ++k) {
        last.set_step(last.step() + 1);
        last.set_t(h * static_cast<double>(last.step()));
        *forged.mutable_reports()->add_reports() = last;
      }
      send_envelope(fd, forged);
    }
    for (std::uint64_t micro = 1; nap(milliseconds(20), stop); ++micro) {
      if (lies.progress) {
        wire::Envelope p;
        p.set_id(e.id());
        p.mutable_progress()->set_step(kSteps - 1);
        p.mutable_progress()->set_micro_steps(micro);
        send_envelope(fd, p);
      }
      if (lies.claim) {
        wire::Envelope c;
        c.set_id(e.id());
        c.mutable_reports()->set_waiting_for("track");
        send_envelope(fd, c);
      }
    }
  };
}

// CASE (wr-xx-jacobi) on SCENE (the paper's) over kSteps macro steps, the
// soil (if any) on a real node: the failure's message and the vehicle's
// address.
std::pair<std::string, std::string> run_against_liar(Lies lies,
                                                     const std::string& case_name = "wr-xx-jacobi",
                                                     const std::string& scene_file = "paper.toml") {
  test::FakeNode vehicle("vehicle", nullptr, {}, lying_reports(lies));
  remote::LaunchedNode track("track_node", milliseconds(10000));
  std::unique_ptr<remote::LaunchedNode> soil;
  if (case_name.find("ss") != std::string::npos)
    soil = std::make_unique<remote::LaunchedNode>("soil_node", milliseconds(10000));
  WithholdingProxy proxy(track.address());
  Scene scene = load_scene(test::source_path("scenes/" + scene_file));
  scene = with_keys(scene, {{"simulation.end_time", kSteps * scene.macro_step}});
  remote::RemoteTimeouts t;
  t.step_min = milliseconds(500);
  t.step_max = milliseconds(1500);
  t.step_budget = milliseconds(4000);
  const remote::ParticipantFactory make =
      [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    const std::string& role = c.participant.role;
    const Address at = role == "vehicle" ? vehicle.address()
                       : role == "soil"  ? soil->address()
                                         : proxy.address();
    return std::make_unique<remote::RemoteParticipant>(at, scene, c, t);
  };
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  try {
    run::run_cosim(scene, parse_case(case_name), o, make, "tcp");
  } catch (const remote::NodeFailure& e) {
    return {e.what(), vehicle.address().str()};
  }
  return {"the run went through", vehicle.address().str()};
}

// `step`: the macro step the run fails at (Gauss-Seidel's track, which
// steps first, waits one step earlier); `reported`: the vehicle's last
// step report.
void expect_vehicle_named(const std::pair<std::string, std::string>& r, long step = 20,
                          long reported = kSteps - 1) {
  const auto& [m, vehicle] = r;
  EXPECT_EQ(m.rfind("vehicle node at " + vehicle + ": ", 0), 0u) << m;
  EXPECT_NE(m.find("vehicle node at " + vehicle + ": no data to its peers within "),
            std::string::npos)
      << m;
  EXPECT_NE(
      m.find(" ms (its last step report was for macro step " + std::to_string(reported) + "; "),
      std::string::npos)
      << m;
  EXPECT_NE(m.find("; the track participant(s) wait for its data: its step reports are no proof it "
                   "sent them) at macro step " +
                   std::to_string(step) + " "),
            std::string::npos)
      << m;
  EXPECT_EQ(m.find("step budget"), std::string::npos) << m;
}

TEST(WithheldData, AVehicleReportingStepsItNeverTookIsNamed) {
  expect_vehicle_named(run_against_liar({}));
}

TEST(WithheldData, ItsProgressFramesDoNotMakeTheTrackExhaustTheBudget) {
  expect_vehicle_named(run_against_liar({true, false}));
}

TEST(WithheldData, ItsForgedClaimToWaitForTheTrackDoesNotShiftTheBlame) {
  expect_vehicle_named(run_against_liar({false, true}));
}

// Its reports held where the track's stop (a tie): the track's claim is
// believed.
TEST(WithheldData, AVehicleWhoseReportsAreHeldToATieIsNamed) {
  Lies tie;
  tie.forge = false;
  tie.claim = true;
  const auto r = run_against_liar(tie);
  EXPECT_EQ(r.first.rfind("vehicle node at " + r.second + ": ", 0), 0u) << r.first;
  EXPECT_NE(r.first.find("the track participant(s) wait for its data"), std::string::npos)
      << r.first;
}

// vehicle | track | soil: the soil has its data from the track, the
// vehicle still owes the track its own.
TEST(WithheldData, WithThreeParticipantsTheVehicleIsNamed) {
  expect_vehicle_named(run_against_liar({}, "wr-xx+ss-xx-jacobi", "soil.toml"));
}

TEST(WithheldData, UnderGaussSeidelTheVehicleIsNamed) {
  expect_vehicle_named(run_against_liar({}, "wr-xx+ss-xx-gauss-seidel", "soil.toml"), 19);
  expect_vehicle_named(run_against_liar({true, true}, "wr-xx+ss-xx-gauss-seidel", "soil.toml"), 19);
}

}  // namespace
}  // namespace railcosim
