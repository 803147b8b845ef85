/// @file
/// @brief The segment file of `sdfccd query` (segment_file.h): values, errors naming the line, and the input
/// bounds (`--segments /dev/zero` must not read until memory runs out).
#include "sdfccd/ccd/segment_file.h"

#include <gtest/gtest.h>

#include <sstream>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

std::vector<SegmentRecord> parse(const std::string& text, double sigma = 0.5) {
  std::istringstream in(text);
  return parseSegments(in, "s.txt", sigma);
}

// The error of parsing `text`, or "" when it is accepted.
std::string errorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SegmentFile, ParsesSegmentsSkippingBlankAndCommentLines) {
  const auto s = parse("# header\n\n 0, 1 ,2,3,4,5\r\n\t-1e3,0,0,1,1,1,0.25\n# end");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].p0, Vec3(0, 1, 2));
  EXPECT_EQ(s[0].p1, Vec3(3, 4, 5));
  EXPECT_EQ(s[0].sigma, 0.5);
  EXPECT_EQ(s[0].line, 3);
  EXPECT_EQ(s[1].p0, Vec3(-1000, 0, 0));
  EXPECT_EQ(s[1].sigma, 0.25);
  EXPECT_EQ(s[1].line, 4);
  EXPECT_TRUE(parse("").empty());
}

TEST(SegmentFile, BadLinesGiveOneLineErrorsNamingTheLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"0,0,0,1,1,1\n0,0,0,1,1\n", "s.txt:2: expected 6 or 7"},
      {"0,0,0,1,1,1,0,5\n", "s.txt:1: expected 6 or 7 comma-separated numbers (x0,y0,z0,x1,y1,z1[,sigma]), got 8"},
      {"\n\n0,0,zero,1,1,1\n", "s.txt:3: 'zero' is not a number"},
      {"0,0,0,1,nan,1\n", "s.txt:1: value 'nan' is not finite"},
      {"0,0,0,1,1,1,inf\n", "s.txt:1: value 'inf' is not finite"},
      {"0,0,0,1,1,1e999\n", "s.txt:1: value '1e999' is not finite"},
      {"0,,0,1,1,1\n", "s.txt:1: empty value 2"},
      {std::string("0,0,0,1,1,1\x00", 12) + "\n", "s.txt:1: a value holds a NUL byte"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string message = errorOf(text);
    EXPECT_EQ(message.rfind(expected, 0), 0u) << "'" << message << "' for " << text;
    EXPECT_EQ(message.find('\n'), std::string::npos);
  }
}

TEST(SegmentFile, EndlessInputEndsWithAnErrorNotExhaustedMemory) {
  // /dev/zero: NUL bytes and no newline, forever.
  try {
    readSegmentFile("/dev/zero", 0.0);
    ADD_FAILURE() << "accepted /dev/zero";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero:1: line longer than 4096 bytes"), std::string::npos) << e.what();
  }
  // A long line of valid-looking digits is refused at the same bound.
  EXPECT_NE(errorOf(std::string(kMaxSegmentLineBytes + 1, '1')).find("s.txt:1: line longer than"), std::string::npos);
  // Exactly at the bound a line is read (and then judged on its values).
  EXPECT_NE(errorOf("1" + std::string(kMaxSegmentLineBytes - 1, ' ')).find("got 1"), std::string::npos);
  EXPECT_THROW(readSegmentFile("/nonexistent/segments.txt", 0.0), Error);
}

}  // namespace
}  // namespace sdfccd
