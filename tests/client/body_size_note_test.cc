#include "client/cli/body_size_note.h"

#include <gtest/gtest.h>

#include "client/cli/body_size_note.cc"  // NOLINT(build/include): BodySizeNote

namespace mocap::cli {
namespace {

v1::SessionSummary Summary(float performer_height, float reach_height, bool estimated) {
  v1::SessionSummary summary;
  summary.set_performer_height(performer_height);
  summary.set_reach_height(reach_height);
  summary.set_performer_height_estimated(estimated);
  return summary;
}

TEST(BodySizeNoteTest, SaysTheSizeTheReachGave) {
  const std::string note = BodySizeNote(Summary(2.0f, 2.0f, true), 1.7f, false);
  EXPECT_NE(note.find("sized by the wrists' reach: 2.00 m"), std::string::npos) << note;
  EXPECT_NE(note.find("the database performer 1.70 m"), std::string::npos) << note;
}

TEST(BodySizeNoteTest, AnUndeclaredBodyTheReachSaidNothingOfAsksForTheHeight) {
  // The reach never sizes a body down: a smaller performer is reconstructed at the database's size.
  const std::string note = BodySizeNote(Summary(1.7f, 1.7f, false), 1.7f, false);
  ASSERT_FALSE(note.empty());
  EXPECT_NE(note.find("database performer's 1.70 m"), std::string::npos) << note;
  EXPECT_NE(note.find("--performer-height"), std::string::npos) << note;
  EXPECT_EQ(note.back(), '\n');
}

TEST(BodySizeNoteTest, ADeclaredBodyIsOnlyToldWhenTheWristsReachedBeyondIt) {
  EXPECT_EQ(BodySizeNote(Summary(1.6f, 1.6f, false), 1.7f, true), "");
  // Within the database bodies' reach the reach height is the database performer's: no evidence
  // against a smaller declared performer (it used to say "declare --performer-height 1.70 or more").
  EXPECT_EQ(BodySizeNote(Summary(1.6f, 1.7f, false), 1.7f, true), "");
  const std::string note = BodySizeNote(Summary(1.6f, 1.9f, false), 1.7f, true);
  EXPECT_NE(note.find("reached as far as a 1.90 m body's (this one is 1.60 m)"), std::string::npos) << note;
  EXPECT_NE(note.find("--performer-height 1.90 or more"), std::string::npos) << note;
}

}  // namespace
}  // namespace mocap::cli
