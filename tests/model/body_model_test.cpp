/// @file
/// @brief BodyModel and the model cache (sdfccd/model/body_model.h, model_cache.h) without Bullet: the body frame,
/// cache entries named by content key (stable names: existing caches stay valid), reloaded identically, and a
/// damaged entry rebuilt.
#include "sdfccd/model/body_model.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/model/mesh_file.h"
#include "sdfccd/model/model_cache.h"
#include "sdfccd/model/model_cache_folder.h"

namespace sdfccd {
namespace {

std::filesystem::path tempFolder(const std::string& name) {
  // One folder per process: test runs of several builds may share the machine.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("sdfccd_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(BodyModel, PrimitiveIsInItsBodyFrame) {
  BodyModelSettings s;
  s.resolution = 16;
  s.points = 200;
  const auto model = BodyModel::buildFromMesh(makeBox(Vec3(0.3, 0.2, 0.1)), s);
  EXPECT_LT(model->unitDensityMassProperties().centerOfMassInMesh.norm(), 1e-12);
  EXPECT_NEAR(model->boundsInBody().sizes().maxCoeff(), 0.6, 1e-12);
  EXPECT_EQ(model->shell().positions.size(), 200u);
  EXPECT_NEAR(model->principalInertia(2.0).x(), 2.0 / 12.0 * (0.4 * 0.4 + 0.2 * 0.2), 1e-12);
  s.scale = -1.0;
  EXPECT_THROW(BodyModel::buildFromMesh(makeBox(Vec3(0.3, 0.2, 0.1)), s), Error);
}

TEST(BodyModel, CacheEntriesAreNamedByContentAndReloadIdentically) {
  if (!canLoadMeshFiles()) GTEST_SKIP() << "this build has no mesh loader";
  const std::string mesh = std::string(SDFCCD_ASSETS_DIR) + "/meshes/bunny.off";
  const std::filesystem::path cache = tempFolder("body_model_cache");
  BodyModelSettings s;
  s.resolution = 16;
  s.padding = 2;
  s.scale = 0.5;
  s.cacheDir = cache.string();
  const auto built = BodyModel::buildFromMeshFile(mesh, s);

  // The key: FNV-1a of the file's bytes, continued over the parameters (as written since the first cache).
  std::ifstream in(mesh, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  ModelCacheKey key;
  key.add(bytes.str()).add("v2 r16 p2 n0 s0.5");
  const std::string stem = (cache / ("bunny-" + key.hex())).string();
  EXPECT_TRUE(std::filesystem::is_regular_file(stem + ".sdf")) << stem;
  EXPECT_TRUE(std::filesystem::is_regular_file(stem + ".ply")) << stem;

  const auto cached = BodyModel::buildFromMeshFile(mesh, s);
  EXPECT_EQ(built->field().grid().values(), cached->field().grid().values());
  EXPECT_EQ(built->shell().positions, cached->shell().positions);
  // A damaged entry is rebuilt and overwritten.
  std::filesystem::resize_file(stem + ".sdf", 10);
  const auto rebuilt = BodyModel::buildFromMeshFile(mesh, s);
  EXPECT_EQ(built->field().grid().values(), rebuilt->field().grid().values());
  EXPECT_GT(std::filesystem::file_size(stem + ".sdf"), 10u);
  std::filesystem::remove_all(cache);
}

TEST(ModelCache, BuildsOnceThenLoads) {
  const std::filesystem::path folder = tempFolder("model_cache");
  const ModelCache cache(folder.string());
  ModelCacheKey key;
  key.add(std::string("a"));
  EXPECT_EQ(key.hex(), "af63dc4c8601ec8c");  // FNV-1a("a")
  EXPECT_EQ(cache.entryPath("box", key, "sdf"), (folder / "box-af63dc4c8601ec8c.sdf").string());
  int builds = 0;
  const auto build = [&] {
    ++builds;
    return std::make_shared<const SdfGrid>(Vec3i(2, 2, 2), Vec3::Zero(), 1.0, std::vector<float>(8, 0.5f));
  };
  const auto first = cache.field("box", key, build);
  const auto second = cache.field("box", key, build);
  EXPECT_EQ(builds, 1);
  EXPECT_EQ(first->values(), second->values());
  // Disabled: every call builds, nothing is written.
  const ModelCache none("");
  none.field("box", key, build);
  EXPECT_EQ(builds, 2);
  std::filesystem::remove_all(folder);
}

/// The damaged versions of a cache entry's bytes the cache must survive: empty, cut at several points,
/// random bytes (seeded), and the entry with every byte after the first line flipped.
std::vector<std::string> damagedVersions(const std::string& good) {
  std::vector<std::string> out = {"", good.substr(0, 1), good.substr(0, 10), good.substr(0, good.size() / 2),
                                  good.substr(0, good.size() - 1)};
  std::mt19937 random(14);
  std::string noise(good.size(), '\0');
  for (char& c : noise) c = static_cast<char>(random() & 0xff);
  out.push_back(noise);
  std::string flipped = good;
  for (std::size_t i = good.find('\n') + 1; i < flipped.size(); ++i) flipped[i] = static_cast<char>(~flipped[i]);
  out.push_back(flipped);
  return out;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A damaged entry is never trusted and never crashes the cache: it is reported with one line on stderr naming the
// file, rebuilt, and overwritten with an intact entry.
TEST(ModelCache, DamagedEntriesAreReportedThenRebuilt) {
  const std::filesystem::path folder = tempFolder("model_cache_damaged");
  const ModelCache cache(folder.string());
  ModelCacheKey key;
  key.add(std::string("damaged"));
  int fieldBuilds = 0;
  const auto buildField = [&] {
    ++fieldBuilds;
    std::vector<float> values(27);
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.25f * static_cast<float>(i) - 3.0f;
    return std::make_shared<const SdfGrid>(Vec3i(3, 3, 3), Vec3(-1, -1, -1), 1.0, std::move(values));
  };
  int shellBuilds = 0;
  const auto buildShell = [&] {
    ++shellBuilds;
    return shellFromVertices(makeBox(Vec3(0.5, 0.25, 0.125)));
  };
  const auto field = cache.field("grid", key, buildField);
  const PointShell shell = cache.shell("box", key, buildShell);
  const std::string fieldPath = cache.entryPath("grid", key, "sdf");
  const std::string shellPath = cache.entryPath("box", key, "ply");
  const std::string goodField = readBytes(fieldPath);
  const std::string goodShell = readBytes(shellPath);
  ASSERT_FALSE(goodField.empty());
  ASSERT_FALSE(goodShell.empty());

  int expectedFieldBuilds = 1;
  for (const std::string& damaged : damagedVersions(goodField)) {
    writeBytes(fieldPath, damaged);
    testing::internal::CaptureStderr();
    const auto reloaded = cache.field("grid", key, buildField);
    const std::string err = testing::internal::GetCapturedStderr();
    ++expectedFieldBuilds;
    EXPECT_EQ(fieldBuilds, expectedFieldBuilds)
        << "a damaged field entry of " << damaged.size() << " bytes was trusted";
    EXPECT_EQ(reloaded->values(), field->values());
    EXPECT_NE(err.find("damaged cache entry '" + fieldPath + "'"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(readBytes(fieldPath), goodField) << "the entry was not rewritten";
  }
  int expectedShellBuilds = 1;
  for (const std::string& damaged : damagedVersions(goodShell)) {
    writeBytes(shellPath, damaged);
    testing::internal::CaptureStderr();
    const PointShell reloaded = cache.shell("box", key, buildShell);
    const std::string err = testing::internal::GetCapturedStderr();
    // A cut that still parses as a complete shell (e.g. only the last newline gone) may load: then it must be
    // the same shell. Everything else is reported and rebuilt.
    if (shellBuilds == expectedShellBuilds) {
      EXPECT_EQ(reloaded.positions, shell.positions) << damaged.size() << " bytes";
      EXPECT_TRUE(err.empty()) << err;
      continue;
    }
    ++expectedShellBuilds;
    EXPECT_EQ(shellBuilds, expectedShellBuilds);
    EXPECT_EQ(reloaded.positions, shell.positions);
    EXPECT_NE(err.find("damaged cache entry '" + shellPath + "'"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(readBytes(shellPath), goodShell);
  }
  EXPECT_GE(expectedShellBuilds, 6);  // the empty, cut, random and flipped versions at least
  std::filesystem::remove_all(folder);
}

// The default folder follows the XDG rule; --cache "" is no cache; an unwritable folder is one line naming it.
TEST(ModelCacheFolder, XdgDefaultAndWritabilityCheck) {
  const char* oldXdg = std::getenv("XDG_CACHE_HOME");
  const char* oldHome = std::getenv("HOME");
  const std::string savedXdg = oldXdg ? oldXdg : "";
  const std::string savedHome = oldHome ? oldHome : "";
  ::setenv("XDG_CACHE_HOME", "/tmp/xdg-test", 1);
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(defaultModelCacheFolder(), "/tmp/xdg-test/sdfccd");
  ::setenv("XDG_CACHE_HOME", "relative/ignored", 1);  // the XDG spec: relative values are ignored
  EXPECT_EQ(defaultModelCacheFolder(), "/home/someone/.cache/sdfccd");
  ::unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(defaultModelCacheFolder(), "/home/someone/.cache/sdfccd");
  ::unsetenv("HOME");
  EXPECT_EQ(defaultModelCacheFolder(), "");
  const std::string given = "/somewhere/else";
  EXPECT_EQ(modelCacheFolder(&given), given);
  const std::string none;
  EXPECT_EQ(modelCacheFolder(&none), "");
  if (oldXdg) ::setenv("XDG_CACHE_HOME", savedXdg.c_str(), 1);
  if (oldHome) ::setenv("HOME", savedHome.c_str(), 1);

  const std::filesystem::path folder = tempFolder("model_cache_folder");
  EXPECT_NO_THROW(checkModelCacheWritable((folder / "a" / "b").string()));  // created
  EXPECT_TRUE(std::filesystem::is_directory(folder / "a" / "b"));
  EXPECT_TRUE(std::filesystem::is_empty(folder / "a" / "b"));  // the probe is gone
  EXPECT_NO_THROW(checkModelCacheWritable(""));
  writeBytes((folder / "file").string(), "x");
  for (const std::filesystem::path& bad : {folder / "file", folder / "file" / "sub"}) {
    try {
      checkModelCacheWritable(bad.string());
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("cache folder '" + bad.string() + "'"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  if (::geteuid() != 0) {  // root writes anywhere
    std::filesystem::create_directories(folder / "readonly");
    std::filesystem::permissions(folder / "readonly",
                                 std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    EXPECT_THROW(checkModelCacheWritable((folder / "readonly").string()), Error);
    std::filesystem::permissions(folder / "readonly", std::filesystem::perms::owner_all);
  }
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace sdfccd
