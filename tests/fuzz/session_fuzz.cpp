// libFuzzer target: arbitrary bytes as a node receives them from a socket,
// through the frame decoder into the session state machine. Whatever the
// bytes, the node must answer or refuse, never crash, hang or leak.
#include <cstddef>
#include <cstdint>

#include "session.hpp"
#include "wire.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace railcosim;
  static const bool quiet = [] {
    google::protobuf::SetLogHandler(nullptr);
    return true;
  }();
  (void)quiet;
  NodeOptions options;
  options.role = "any";  // whatever participant the bytes ask for
  // A small budget keeps every unit fast: what is fuzzed is the decoding and
  // the state machine, not how long a runaway step may grind.
  options.max_micro_steps = 256;
  NodeSession session(options);
  FrameDecoder decoder(1 << 20);
  decoder.feed(reinterpret_cast<const char*>(data), size);
  wire::Envelope request;
  while (decoder.next(request) == FrameDecoder::Status::kFrame) {
    bool close = false;
    const wire::Envelope reply = session.handle(request, close);
    if (reply.body_case() == wire::Envelope::BODY_NOT_SET) __builtin_trap();  // always an answer
    if (close) break;
  }
  return 0;
}
