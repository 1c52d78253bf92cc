// The names of the transports, as users give them (--transport, study
// plans) and read them (summary.json, the study's folders and report):
// spelled here only. Each is the name of one class of transport.cpp, whose
// table (transport.hpp: transport_names(), find_transport()) says what a
// name means.
#pragma once

namespace railcosim::remote {

inline constexpr char kInprocTransport[] = "inproc";  // the participants in the master
inline constexpr char kTcpTransport[] = "tcp";        // each in a node process, over TCP

}  // namespace railcosim::remote
