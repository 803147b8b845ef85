// parseShell (point_shell.h): the in-memory reader the fuzzer drives (tests/fuzz/fuzz_shell_loader) reads
// exactly what loadShell reads from a file, and the inputs the fuzzer found are rejected with one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/shell/point_shell.h"

namespace sdfccd {
namespace {

std::string parseError(const std::string& text, const std::string& name) {
  try {
    parseShell(text, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ShellParse, FromMemoryEqualsFromFile) {
  ShellSamplingSettings settings;
  settings.points = 40;
  settings.iterations = 2;
  const PointShell shell = sampleShell(makeIcosphere(0.5, 1), settings);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sdfccd-shell-parse-test";
  std::filesystem::create_directories(dir);
  for (const char* name : {"s.ply", "s.csv"}) {
    const std::string file = (dir / name).string();
    saveShell(shell, file);
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const PointShell fromFile = loadShell(file);
    const PointShell fromMemory = parseShell(text.str(), name);
    ASSERT_EQ(fromMemory.size(), shell.size()) << name;
    EXPECT_EQ(fromMemory.positions, fromFile.positions) << name;
    EXPECT_EQ(fromMemory.normals, fromFile.normals) << name;
  }
  std::filesystem::remove_all(dir);
  EXPECT_NE(parseError("x,y,z,nx,ny,nz\n", "shell.obj").find("unknown shell format"), std::string::npos);
}

// A 200-byte PLY whose header claims 150 million points: the count only bounds the loop, it never sizes a
// reservation (3.6 GB before the truncation is found), so the file is rejected as truncated, at once. (The memory
// bound itself is checked by the fuzzer's -rss_limit_mb.)
TEST(ShellParse, HugeVertexCountInATinyFileIsTruncatedNotAllocated) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 150000000\nproperty double x\nproperty double y\n"
      "property double z\nproperty double nx\nproperty double ny\nproperty double nz\nend_header\n";
  const std::string message = parseError(header + "0 0 0 0 0 1\n", "big.ply");
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
  EXPECT_NE(message.find("150000000"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

}  // namespace
}  // namespace sdfccd
