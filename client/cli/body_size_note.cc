#include "client/cli/body_size_note.h"

#include <iomanip>
#include <sstream>

namespace mocap::cli {

std::string BodySizeNote(const v1::SessionSummary& summary, float database_height, bool declared) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(2);
  if (summary.performer_height_estimated()) {
    out << "  body sized by the wrists' reach: " << summary.performer_height() << " m tall (the database performer "
        << database_height << " m; --performer-height to declare, --no-estimate-height to keep the database's)\n";
  } else if (summary.reach_height() > 1.02f * summary.performer_height() &&
             summary.reach_height() > 1.001f * database_height) {
    // reach_height is the database performer's height while the wrists stayed within its bodies'
    // reach: that floor is no evidence against a declared smaller performer.
    out << "  the wrists reached as far as a " << summary.reach_height() << " m body's (this one is "
        << summary.performer_height() << " m): declare --performer-height " << summary.reach_height() << " or more\n";
  } else if (!declared) {
    // The reach is one-sided evidence: nothing in it tells a smaller performer.
    out << "  body at the database performer's " << summary.performer_height()
        << " m: the wrists' reach shows a larger body only, never a smaller one; for a performer of "
           "another size declare --performer-height (undeclared, 15% smaller errs about 5 times more)\n";
  }
  return out.str();
}

}  // namespace mocap::cli
