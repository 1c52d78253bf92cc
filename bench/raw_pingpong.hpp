// The baseline of the network benchmark: a round trip of plain POSIX TCP
// sockets on loopback (TCP_NODELAY, blocking send/recv, nothing else),
// between this process and a forked child that answers every request.
#pragma once

#include <cstddef>

namespace railcosim {

struct RawRoundTrip {
  std::size_t request_bytes = 0, reply_bytes = 0;
  int samples = 0;
  double p10_us = 0, median_us = 0, p90_us = 0;
};

// `samples` timed round trips (after 200 untimed ones): each sends
// `request_bytes` to the child and waits for its `reply_bytes`. Throws
// std::runtime_error naming the call that failed.
RawRoundTrip raw_round_trip(std::size_t request_bytes, std::size_t reply_bytes, int samples);

}  // namespace railcosim
