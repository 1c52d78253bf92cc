// The conformance kit's check of the direct plane's link handshake
// (docs/protocol.md §17): a participant that has been handed its peer links
// refuses a hello with the wrong session key (UNAUTHORIZED) and one from a
// participant it does not expect (WRONG_ROLE), and keeps waiting for the
// expected peer.
#pragma once

#include <string>

#include "cli/conform.hpp"
#include "connection.hpp"
#include "participant.hpp"

namespace railcosim::cli {

// `master`: a session of the subject, configured and initialized, on which
// nothing else will be sent (the check ends it). Returns "" when both
// refusals hold, "skipped: ..." when the subject does not offer the direct
// plane, else what went wrong.
std::string check_peer_refusals(Connection& master, const SubsystemConfig& config,
                                const ConformOptions& o);

}  // namespace railcosim::cli
