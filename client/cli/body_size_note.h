// What `mocap reconstruct` says of the body's size (issue #22: a user always brings somebody new).
// The wrists' reach sizes a body up when they reach beyond the database's bodies, and never down:
// a performer smaller than the database's, or a larger one who keeps the hands low, is
// reconstructed at the database performer's size unless the height is declared, and errs several
// times more (docs/evaluation.md, stop 83). The summary says which of these happened.
#pragma once

#include <string>

#include "mocap/v1/reconstruction.pb.h"

namespace mocap::cli {

// One line (with its newline) for the human summary: the size the reach gave, or that the wrists
// reached further than the body's size (declared or not), or, undeclared (`declared`: neither
// --performer-height nor --target-rig), that nothing told its size; empty when there is nothing to
// say. `database_height`: SessionStarted.database_height.
std::string BodySizeNote(const v1::SessionSummary& summary, float database_height, bool declared);

}  // namespace mocap::cli
