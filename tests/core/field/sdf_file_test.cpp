/// @file
/// @brief Native and SDFGen SDF files: round trips, format details, and rejection of every kind of bad file.
#include "sdfccd/field/sdf_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

SdfGrid sampleGrid() {
  const Vec3i n(4, 3, 5);
  std::vector<float> v;
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i)
        v.push_back(static_cast<float>(std::sin(i + 2.1 * j - 0.7 * k) * 0.37 + 1e-7 * i));
  v[7] = -0.0f;
  v[8] = 1.17549435e-38f;  // smallest normal float survives text round trips too
  return SdfGrid(n, Vec3(-0.125, 1.0 / 3.0, 2.5e-3), 0.1 + 1e-12, std::move(v));
}

void expectSame(const SdfGrid& a, const SdfGrid& b) {
  EXPECT_EQ(a.nodeCounts(), b.nodeCounts());
  EXPECT_EQ(a.origin(), b.origin());
  EXPECT_EQ(a.spacing(), b.spacing());
  ASSERT_EQ(a.values().size(), b.values().size());
  EXPECT_EQ(std::memcmp(a.values().data(), b.values().data(), a.values().size() * sizeof(float)), 0);
}

// Independent FNV-1a 64 (from its published definition) to forge files with valid checksums.
std::uint64_t referenceFnv1a(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}
void putLe(std::string& s, std::size_t at, std::uint64_t v, int bytes) {
  for (int b = 0; b < bytes; ++b) s[at + b] = static_cast<char>((v >> (8 * b)) & 0xff);
}
void putDouble(std::string& s, std::size_t at, double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, 8);
  putLe(s, at, bits, 8);
}
// Recomputes the trailing checksum after editing a native file.
void reseal(std::string& s) {
  putLe(s, s.size() - 8, referenceFnv1a(s.substr(0, s.size() - 8)), 8);
}

void expectRejected(const std::string& bytes, const std::string& what) {
  try {
    parseSdf(bytes, "test.sdf");
    ADD_FAILURE() << "accepted: " << what;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("test.sdf"), std::string::npos) << message;
  }
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "sdfccd-file-test-" + std::to_string(::getpid()) + "-" + name;
}

TEST(SdfFile, NativeRoundTripIsExactAndLittleEndian) {
  const SdfGrid grid = sampleGrid();
  const std::string bytes = serializeSdf(grid, SdfFileFormat::Native);
  ASSERT_EQ(bytes.size(), 64u + 4u * 60u + 8u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("sdfccd\x1a\n", 8));
  EXPECT_EQ(bytes[8], 1);   // version 1, little-endian
  EXPECT_EQ(bytes[16], 4);  // ni
  EXPECT_EQ(bytes[20], 3);  // nj
  EXPECT_EQ(bytes[24], 5);  // nk
  double spacing;
  std::memcpy(&spacing, bytes.data() + 56, 8);  // this test host is little-endian (x86-64 / arm64)
  EXPECT_EQ(spacing, grid.spacing());
  std::uint64_t stored = 0;
  for (int b = 0; b < 8; ++b)
    stored |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[bytes.size() - 8 + b])) << (8 * b);
  EXPECT_EQ(stored, referenceFnv1a(bytes.substr(0, bytes.size() - 8)));
  expectSame(parseSdf(bytes, "mem"), grid);
}

TEST(SdfFile, SdfGenLayoutAndRoundTrips) {
  const SdfGrid grid = sampleGrid();
  const std::string text = serializeSdf(grid, SdfFileFormat::SdfGen);
  std::istringstream in(text);
  int ni, nj, nk;
  double ox, oy, oz, dx;
  in >> ni >> nj >> nk >> ox >> oy >> oz >> dx;
  EXPECT_EQ(Vec3i(ni, nj, nk), grid.nodeCounts());
  EXPECT_EQ(Vec3(ox, oy, oz), grid.origin());
  EXPECT_EQ(dx, grid.spacing());
  double first, second;
  in >> first >> second;  // i fastest
  EXPECT_EQ(static_cast<float>(first), grid.value(0, 0, 0));
  EXPECT_EQ(static_cast<float>(second), grid.value(1, 0, 0));
  expectSame(parseSdf(text, "mem"), grid);
  // native -> SDFGen -> native
  const SdfGrid back = parseSdf(serializeSdf(parseSdf(text, "a"), SdfFileFormat::Native), "b");
  expectSame(back, grid);
  // A hand-written SDFGen file with CRLF line ends, tabs and exponents.
  std::string hand = "2 2 2\r\n0 0 0\r\n0.5\r\n";
  for (int n = 0; n < 8; ++n) hand += (n % 2 ? "\t-1e-1\r\n" : "+2.5E0\n");
  const SdfGrid parsed = parseSdf(hand, "hand");
  EXPECT_FLOAT_EQ(parsed.value(1, 1, 1), -0.1f);
  EXPECT_FLOAT_EQ(parsed.value(0, 1, 1), 2.5f);
}

TEST(SdfFile, SaveAndLoadThroughFilesPickTheFormat) {
  const SdfGrid grid = sampleGrid();
  const std::string native = tempPath("a.sdf");
  const std::string text = tempPath("a.sdfgen");
  saveSdf(native, grid);
  saveSdf(text, grid);
  std::ifstream t(text);
  std::string firstLine;
  std::getline(t, firstLine);
  EXPECT_EQ(firstLine, "4 3 5");
  expectSame(loadSdf(native), grid);
  expectSame(loadSdf(text), grid);
  const std::string forced = tempPath("b.sdfgen");
  saveSdf(forced, grid, SdfFileFormat::Native);  // an explicit format wins over the extension
  std::ifstream f(forced, std::ios::binary);
  char magic[6] = {};
  f.read(magic, 6);
  EXPECT_EQ(std::string(magic, 6), "sdfccd");
  EXPECT_EQ(sdfFileFormatForPath("x.sdfgen"), SdfFileFormat::SdfGen);
  EXPECT_EQ(sdfFileFormatForPath("x.sdf"), SdfFileFormat::Native);
  EXPECT_EQ(parseSdfFileFormat("sdfgen"), SdfFileFormat::SdfGen);
  EXPECT_THROW(parseSdfFileFormat("vtk"), Error);
  for (const auto& p : {native, text, forced}) std::remove(p.c_str());
}

TEST(SdfFile, MissingFilesAndUnwritablePathsFailCleanly) {
  try {
    loadSdf("/nonexistent/field.sdf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/field.sdf"), std::string::npos);
  }
  EXPECT_THROW(saveSdf("/nonexistent/dir/out.sdf", sampleGrid()), Error);
  EXPECT_THROW(loadSdf(::testing::TempDir()), Error);  // a directory
}

TEST(SdfFile, RejectsCorruptNativeFiles) {
  const std::string good = serializeSdf(sampleGrid(), SdfFileFormat::Native);
  // Every truncation, including an empty file and a partial magic.
  for (std::size_t length = 0; length < good.size(); ++length) expectRejected(good.substr(0, length), "truncated");
  // Trailing garbage.
  expectRejected(good + "x", "trailing byte");
  // Any single flipped bit in header or values breaks the checksum (or the header checks).
  for (std::size_t at : {8u, 17u, 33u, 60u, 64u, 100u, 300u, 311u}) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    expectRejected(bad, "flipped bit at " + std::to_string(at));
  }
  // Header lies with valid checksums: version, value type, huge node counts, bad spacing, NaN values.
  auto forged = [&](auto edit) {
    std::string s = good;
    edit(s);
    reseal(s);
    return s;
  };
  expectRejected(forged([](std::string& s) { putLe(s, 8, 2, 4); }), "version 2");
  expectRejected(forged([](std::string& s) { putLe(s, 12, 7, 4); }), "value type");
  expectRejected(forged([](std::string& s) { putLe(s, 16, 0xffffffffu, 4); }), "huge ni");
  expectRejected(forged([](std::string& s) {
                   putLe(s, 20, 60000, 4);
                   putLe(s, 24, 60000, 4);
                 }),
                 "size lie");
  expectRejected(forged([](std::string& s) { putLe(s, 16, 1, 4); }), "ni = 1");
  expectRejected(forged([](std::string& s) { putDouble(s, 56, 0.0); }), "zero spacing");
  expectRejected(forged([](std::string& s) { putDouble(s, 56, -0.1); }), "negative spacing");
  expectRejected(forged([](std::string& s) { putDouble(s, 56, std::numeric_limits<double>::infinity()); }), "inf");
  expectRejected(forged([](std::string& s) { putDouble(s, 40, std::nan("")); }), "NaN origin");
  // A finite spacing whose box is not: 1e308 * (nodes - 1) overflows; 1e-300 has no finite inverse.
  expectRejected(forged([](std::string& s) { putDouble(s, 56, 1e308); }), "spacing 1e308");
  expectRejected(forged([](std::string& s) { putDouble(s, 56, 1e-300); }), "spacing 1e-300");
  expectRejected(forged([](std::string& s) { putDouble(s, 32, 1e200); }), "origin 1e200");
  expectRejected(forged([](std::string& s) { putLe(s, 64 + 4 * 5, 0x7fc00000u, 4); }), "NaN value");
  expectRejected(forged([](std::string& s) { putLe(s, 64, 0x7f800000u, 4); }), "inf value");
}

TEST(SdfFile, RejectsCorruptSdfGenFiles) {
  const std::string good = serializeSdf(sampleGrid(), SdfFileFormat::SdfGen);
  expectRejected(good.substr(0, good.size() / 2), "truncated values");
  expectRejected(good.substr(0, 3), "truncated header");
  expectRejected(good + "0.5\n", "one value too many");
  expectRejected(good + "garbage\n", "trailing garbage");
  expectRejected("1 2 2\n0 0 0\n1\n0 0 0 0\n", "ni = 1");
  expectRejected("-2 2 2\n0 0 0\n1\n0 0 0 0 0 0 0 0\n", "negative ni");
  expectRejected("60000 60000 60000\n0 0 0\n1\n0 0 0\n", "absurd size, tiny file");
  expectRejected("99999999999999999999 2 2\n0 0 0\n1\n", "overflowing count");
  expectRejected("2 2 2\n0 0 0\n0\n0 0 0 0 0 0 0 0\n", "zero spacing");
  expectRejected("2 2 2\n0 0 0\n-1\n0 0 0 0 0 0 0 0\n", "negative spacing");
  expectRejected("2 2 2\n0 nan 0\n1\n0 0 0 0 0 0 0 0\n", "NaN origin");
  expectRejected("2 2 2\n0 0 0\n1e308\n0 0 0 0 0 0 0 0\n", "spacing 1e308 (a box past the double range)");
  expectRejected("2 2 2\n0 0 0\n1\n0 0 0 nan 0 0 0 0\n", "NaN value");
  expectRejected("2 2 2\n0 0 0\n1\n0 0 0 1e39 0 0 0 0\n", "value beyond float");
  expectRejected("2 2 2\n0 0 0\n1\n0 0 0 0x1 0 0 0 0\n", "hex value");
  expectRejected("2 2 2\n0 0 0\n1\n0 0 0 1,5 0 0 0 0\n", "comma decimal");
  expectRejected("2 2.5 2\n0 0 0\n1\n0 0 0 0 0 0 0 0\n", "fractional count");
}

TEST(SdfFile, RejectsRandomBytesWithoutCrashing) {
  std::mt19937 rng(2024);
  const std::string good = serializeSdf(sampleGrid(), SdfFileFormat::Native);
  for (int trial = 0; trial < 300; ++trial) {
    std::string bytes(static_cast<std::size_t>(rng() % 400), '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    if (trial % 3 == 0 && bytes.size() >= 8) std::memcpy(bytes.data(), good.data(), 8);  // valid magic
    if (trial % 3 == 1) bytes = "3 3 3\n" + bytes;                                       // text header
    expectRejected(bytes, "random bytes " + std::to_string(trial));
  }
}

}  // namespace
}  // namespace sdfccd
