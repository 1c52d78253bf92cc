// One co-simulation session on a node, independent of any socket: the
// protocol's state machine around one Participant (the built-in Subsystem,
// or one an outside program supplies through NodeOptions::make_participant).
//
//   hello [-> challenge/auth] -> configure -> statics* -> initialize ->
//       { set_inputs, get_outputs, step, save, restore, get_results }* -> shutdown
// (the steps may come in a lock step: session_lockstep.cpp)
//
// Every request gets exactly one reply. A request that breaks the protocol
// gets an error reply and ends the session (the node then serves the next).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "participant_setup.hpp"
#include "peer_links.hpp"
#include "scene.hpp"
#include "scene_checks.hpp"
#include "subsystem.hpp"
#include "window_runner.hpp"
#include "wire.hpp"
#include "work_budget.hpp"

namespace railcosim {

// The shortest interval between two progress frames a node sends, whatever
// the master asks (Configure.progress_ms).
inline constexpr std::uint32_t kMinProgressMs = 100;

// The largest mesh a node accepts: kMaxSleepers, kMaxElementsPerSpan
// (scene_checks.hpp, where the master applies them too).

// Builds the participant a session serves from what Configure gives it
// (ParticipantSetup: its interfaces as the master describes them, the run's
// settings, its own configuration); the scene is not read. Throw
// BadRequestError to refuse the settings or the configuration
// (BAD_REQUEST), BadInterfaceError or another std::invalid_argument to
// refuse an interface (BAD_INTERFACE), with a message naming what is wrong.
using SetupBuilder = std::function<std::unique_ptr<Participant>(const ParticipantSetup&)>;

// The product's model's builder: from the scene the master sent, parsed as
// the master parsed it, and this participant's part of the product's model
// (SubsystemConfig). The built-in participants are built so; an outside
// participant takes a SetupBuilder. Exceptions as for SetupBuilder.
using ParticipantBuilder =
    std::function<std::unique_ptr<Participant>(const Scene&, const SubsystemConfig&)>;

// The file of --config: its name, its text, and the table that is the
// participant's own configuration (empty: the table named after the
// participant the session serves).
struct ConfigFile {
  std::string path;
  std::string text;
  std::string table;
};

struct NodeOptions {
  std::string role = "vehicle";       // the participant this node serves, or "any"
  std::optional<Scene> pinned_scene;  // when set, only this scene is accepted
  std::optional<std::string> token;   // when set, a master must prove it knows it
  long max_micro_steps = Newmark::kMaxStepsPerInterval;  // per macro step
  std::string name = "node";
  ParticipantBuilder make_participant;  // empty: the built-in Subsystem
  SetupBuilder configure;               // set: builds the participant (make_participant unused)
  // Set: the participant's own configuration is this file's table, not the
  // master's Configure.own_config (with `configure` only).
  std::optional<ConfigFile> config_file;
};

class NodeSession {
 public:
  explicit NodeSession(const NodeOptions& options) : options_(options) {}

  // Handles one request. `close` is set when the session must end after the
  // reply is sent (shutdown, or an error).
  wire::Envelope handle(const wire::Envelope& request, bool& close);

  // The macro step the session is at (-1 before initialize), for logs.
  long step() const { return step_; }
  const std::string& description() const { return description_; }

  // Direct data plane: where other nodes' peer links are handed over, and how
  // a window's step reports reach the master (one encoded frame per call,
  // from the thread that handles the window).
  const std::shared_ptr<PeerInbox>& inbox() const { return inbox_; }
  void set_report_sink(std::function<void(const std::string&)> sink) { report_ = std::move(sink); }
  // The node's frame limit, which report frames respect.
  void set_max_frame_bytes(std::size_t bytes) { max_frame_bytes_ = bytes; }
  // Whether the master has closed its connection (asked while links open).
  void set_master_gone(std::function<bool()> probe) { master_gone_ = std::move(probe); }
  // Lock step: how the thread that runs it reads the master's next request
  // (false: the master closed the connection; throws ProtocolError).
  void set_request_source(std::function<bool(wire::Envelope&)> source) {
    next_request_ = std::move(source);
  }

 private:
  enum class State { kAwaitHello, kAwaitAuth, kAwaitConfigure, kConfigured };
  wire::Envelope hello_reply(std::uint64_t id) const;
  // SCENE_MISMATCH unless the hello's fingerprint is the pinned scene's.
  void check_pinned_scene() const;
  // WRONG_ROLE unless the hello asks for the participant this node serves.
  void check_hello_target() const;
  // Picks the handler of a request by the session's state and the request's
  // kind; each handler below throws ProtocolError for what breaks the protocol.
  wire::Envelope dispatch(const wire::Envelope& request, bool& close);
  // Before configure: the hello, the answer to the challenge, configure.
  wire::Envelope on_hello(const wire::Envelope& request);
  wire::Envelope on_auth(const wire::Envelope& request);
  wire::Envelope on_configure(const wire::Envelope& request);
  // Configure's checks of the scene and the numbers (the scene it names), and
  // of the interfaces (this participant's configuration from them).
  Scene configured_scene(const wire::Configure& configure) const;
  SubsystemConfig configured_subsystem(const Scene& scene, const wire::Configure& configure) const;
  // The participant built by the product's model's builder (or the built-in
  // Subsystem), or by the SetupBuilder from what Configure says
  // (session_setup.cpp).
  std::unique_ptr<Participant> built_participant(const wire::Configure& configure) const;
  ParticipantSetup configured_setup(const wire::Configure& configure) const;
  // Once configured (session_handlers.cpp): one handler per request kind.
  wire::Envelope on_statics(const wire::Envelope& request);
  wire::Envelope on_initialize(const wire::Envelope& request);
  wire::Envelope on_set_inputs(const wire::Envelope& request);
  wire::Envelope on_get_outputs(const wire::Envelope& request);
  wire::Envelope on_step(const wire::Envelope& request);
  wire::Envelope on_get_results(const wire::Envelope& request);
  wire::Envelope on_save(const wire::Envelope& request);
  wire::Envelope on_restore(const wire::Envelope& request);
  wire::Envelope links(const wire::Envelope& request);
  wire::Envelope window(const wire::Envelope& request);
  // Serves step requests read through the request source until one of
  // another kind comes, whose reply it returns (session_lockstep.cpp).
  wire::Envelope lockstep(const wire::Envelope& request, bool& close);
  // Restores the checkpoint kept by a Save with `keep` (OUT_OF_ORDER if none).
  void restore_kept(Participant& participant);
  // Substep waveforms (session_waveform.cpp): recording on or off, and a
  // step's inputs as waveforms; a participant that refuses is BAD_REQUEST.
  wire::Envelope record_samples(const wire::Envelope& request);
  void take_waveforms(long n, const wire::InputWaveforms& waveforms, bool with_inputs);
  // While a step, a window or a statics works: progress frames to the master, if its
  // configure asked for them (session_handlers.cpp). `step`: the macro step
  // being worked on.
  void watch_progress(std::optional<ScopedWorkProgress>& scope, std::uint64_t id,
                      std::function<long()> step);
  // Refuses (BAD_REQUEST) waveforms whose counts do not fit this participant
  // or whose times lie outside macro step n, before anything is allocated.
  void check_waveforms(long n, const wire::InputWaveforms& waveforms) const;

  NodeOptions options_;
  State state_ = State::kAwaitHello;
  std::uint64_t fingerprint_ = 0;
  std::string participant_;  // named by the hello
  std::string hello_nonce_;  // the master's challenge, which the node's proof covers
  bool peer_hello_ = false;  // the hello came from a peer, not a master
  std::string peer_of_;
  std::string nonce_;
  std::unique_ptr<Participant> served_;  // the participant this session drives
  double macro_step_ = 0;
  InputShape in_shape_;          // the counts of the inputs, from the scene
  std::size_t max_samples_ = 0;  // of an input waveform in one macro step
  long step_ = -1;
  bool record_ = false;  // step reports carry the step's samples
  std::string description_ = "not configured";
  CouplingData outputs_;  // at the current point, for the first window
  std::shared_ptr<PeerInbox> inbox_ = std::make_shared<PeerInbox>();
  std::optional<LinksPlan> links_;
  std::unique_ptr<WindowRunner> runner_;
  std::function<void(const std::string&)> report_;
  std::function<bool()> master_gone_;
  std::function<bool(wire::Envelope&)> next_request_;
  std::optional<ParticipantState> kept_;  // Save with `keep`: the node's own checkpoint
  std::size_t max_frame_bytes_ = kDefaultMaxFrameBytes;
  std::chrono::milliseconds progress_every_{0};  // 0: no progress frames
};

}  // namespace railcosim
