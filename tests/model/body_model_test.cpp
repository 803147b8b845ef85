/// @file
/// @brief BodyModel and the model cache (sdfccd/model/body_model.h, model_cache.h) without Bullet: the body frame,
/// cache entries named by content key (stable names: existing caches stay valid), reloaded identically, and a
/// damaged entry rebuilt.
#include "sdfccd/model/body_model.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/model/mesh_file.h"
#include "sdfccd/model/model_cache.h"

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
  key.add(bytes.str()).add("v1 r16 p2 n0 s0.5");
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

}  // namespace
}  // namespace sdfccd
