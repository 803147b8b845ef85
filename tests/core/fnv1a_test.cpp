/// @file
/// @brief fnv1a (sdfccd/fnv1a.h) against the published FNV-1a 64-bit test vectors, and continuation.
#include "sdfccd/fnv1a.h"

#include <gtest/gtest.h>

#include <string>

namespace sdfccd {
namespace {

TEST(Fnv1a, PublishedVectors) {
  EXPECT_EQ(fnv1a(std::string()), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a(std::string("a")), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a(std::string("foobar")), 0x85944171f73967e8ull);
}

TEST(Fnv1a, ContinuesOverSeveralBuffers) {
  const std::string foo = "foo";
  EXPECT_EQ(fnv1a(std::string("bar"), fnv1a(foo)), fnv1a(std::string("foobar")));
  const unsigned char bytes[] = {'f', 'o', 'o', 'b', 'a', 'r'};
  EXPECT_EQ(fnv1a(bytes + 3, 3, fnv1a(bytes, 3)), fnv1a(std::string("foobar")));
}

}  // namespace
}  // namespace sdfccd
