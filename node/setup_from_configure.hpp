// The participant's setup a Configure message describes, checked as a node
// checks it (a positive macro step, a tolerance not negative, micro steps
// within bounds, each interface's values finite and its quantities known),
// its own configuration left empty for the caller. A node gives its
// participant this (NodeSession::configured_setup); the master gives it to
// a participant it hosts in its own process from the same message
// (master/remote/inproc_fmu.cpp), so that both see the same interfaces.
#pragma once

#include <string>

#include "participant_setup.hpp"
#include "wire.hpp"

namespace railcosim {

// Throws ProtocolError (BAD_REQUEST) naming what is wrong.
ParticipantSetup setup_from_configure(const wire::Configure& c, const std::string& participant,
                                      long max_micro_steps);

}  // namespace railcosim
