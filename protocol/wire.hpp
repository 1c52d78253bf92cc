// The only code that encodes and decodes the wire format: frames, and the
// conversions between protocol messages and the engine's types.
//
// A frame is a 4-byte big-endian payload length followed by that many bytes:
// one serialised railcosim.wire.Envelope. A frame longer than the limit is
// refused before any of its payload is read.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "cosim_case.hpp"
#include "participant.hpp"
#include "railcosim.pb.h"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim {

inline constexpr std::uint32_t kProtocolVersion = 4;
inline constexpr std::size_t kFrameHeaderBytes = 4;
// The largest frame accepted by default: a saved state of a 2,500-sleeper
// track (3 x 12,500 doubles) fits 25 times over.
inline constexpr std::size_t kDefaultMaxFrameBytes = 8u << 20;

// A violation of the protocol by a peer, with the code its error reply carries.
class ProtocolError : public std::runtime_error {
 public:
  ProtocolError(wire::Error::Code code, const std::string& what)
      : std::runtime_error(what), code_(code) {}
  wire::Error::Code code() const { return code_; }

 private:
  wire::Error::Code code_;
};

// Header plus payload. Throws ProtocolError(FRAME_TOO_LARGE) above max_bytes.
std::string encode_frame(const wire::Envelope& envelope,
                         std::size_t max_bytes = kDefaultMaxFrameBytes);
std::uint32_t decode_frame_length(const unsigned char header[kFrameHeaderBytes]);

// Splits a byte stream into envelopes.
class FrameDecoder {
 public:
  enum class Status {
    kNeedMore,  // no complete frame yet
    kFrame,     // one envelope decoded
    kTooLarge,  // the announced length exceeds the limit (the stream is lost)
    kBadFrame,  // the payload is not an envelope (the stream is lost)
  };
  explicit FrameDecoder(std::size_t max_bytes = kDefaultMaxFrameBytes) : max_(max_bytes) {}
  void feed(const char* data, std::size_t n) { buffer_.append(data, n); }
  Status next(wire::Envelope& out);
  std::size_t buffered() const { return buffer_.size(); }
  // The length announced by the frame at the head of the buffer (0 if unknown).
  std::uint32_t announced() const;

 private:
  std::size_t max_;
  std::string buffer_;
};

// Name of the message an envelope carries ("hello", "step", ...), for logs.
std::string body_name(const wire::Envelope& envelope);

// The opening messages of a session, as a master sends them.
wire::Envelope hello_envelope(const std::string& participant, std::uint64_t scene_fingerprint,
                              std::uint32_t protocol_version = kProtocolVersion);
// Configure for one participant: its interfaces (with the peers' roles) and,
// for built-in nodes, the model section.
wire::Envelope configure_envelope(const Scene& scene, const SubsystemConfig& config,
                                  bool with_model = true);

wire::Envelope error_envelope(std::uint64_t id, wire::Error::Code code, const std::string& message,
                              long step = -1, double t = 0.0);

// Engine types <-> messages. from_wire() throws ProtocolError(BAD_REQUEST)
// for a message that does not describe a valid value.
// The scene a Configure carries (its text and files, parsed as the master
// parsed them); throws ProtocolError(BAD_SCENE) naming the key of a bad one.
Scene scene_from_wire(const wire::Configure& configure);
// 64-bit FNV-1a over the scene's canonical text and the files it names (name,
// a zero byte, contents, a zero byte, each): the same on every machine.
std::uint64_t scene_fingerprint(const Scene& scene);
std::uint64_t fnv1a64(std::string_view bytes);

wire::Interface to_wire(const Scene& scene, const InterfaceSpec& spec);
// Rebuilds an interface of the built-in model; throws
// ProtocolError(BAD_INTERFACE) for one it cannot honour.
InterfaceSpec from_wire(const wire::Interface& w);

wire::CouplingData to_wire(const CouplingData& data);
// Appends one interface's values to `out` (a peer link sends a subset).
void to_wire(const InterfaceData& data, wire::InterfaceData* out);
CouplingData from_wire(const wire::CouplingData& data);

wire::StepReport to_wire(const StepResult& result, long step, double t);
StepResult from_wire(const wire::StepReport& report);

// Substep waveforms (wire_waveform.cpp): a step's samples in its report, and
// input waveforms as the receiver rebuilds them, bit for bit. from_wire()
// throws ProtocolError(BAD_REQUEST) for a degree outside 0..3, values that
// are not `width` per sample or not finite, times that do not increase, or
// no sample at all (nothing is allocated for a width before).
void to_wire(const OutputSamples& samples, wire::StepReport* report);
OutputSamples samples_from_wire(const wire::StepReport& report);
wire::InputWaveforms to_wire(const InputWaveforms& waveforms);
InputWaveforms from_wire(const wire::InputWaveforms& waveforms);

}  // namespace railcosim
