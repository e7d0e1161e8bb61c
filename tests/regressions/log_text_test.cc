// Issue #14, finding 3: client-supplied strings cannot forge or flood log lines.
#include "server/log_text.h"

#include <gtest/gtest.h>

#include <string>

namespace mocap {
namespace {

TEST(LogTextTest, EscapesLineBreaksQuotesAndControlCharacters) {
  EXPECT_EQ(LogText("walk\ninfo: request=9 method=DeleteDatabase code=OK"),
            "walk\\ninfo: request=9 method=DeleteDatabase code=OK");
  EXPECT_EQ(LogText("a\"b\\c\r\t\x1b[31m"), "a\\\"b\\\\c\\r\\t\\x1b[31m");
  EXPECT_EQ(LogText(std::string("nul\0here", 8)), "nul\\x00here");
  EXPECT_EQ(LogText("caf\xc3\xa9"), "caf\\xc3\\xa9");  // bytes outside printable ASCII, escaped
}

TEST(LogTextTest, CutsLongTextAndSaysHowMuchWasLeftOut) {
  const std::string label(100'000, 'x');
  const std::string logged = LogText(label);
  EXPECT_LT(logged.size(), 300u);
  EXPECT_NE(logged.find("(+99800 bytes)"), std::string::npos) << logged;
  EXPECT_EQ(LogText("short"), "short");
}

}  // namespace
}  // namespace mocap
