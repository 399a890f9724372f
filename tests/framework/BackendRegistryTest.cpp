// Collision back-ends in the registry: registered under a name for a kind of
// target, found and created by that pair, listed per kind; a second
// registration of the same pair is an error naming both plugins.
#include <gtest/gtest.h>

#include "framework/core/CollisionBackend.h"
#include "framework/core/Registry.h"

namespace trephine {
namespace {

class FirstBackend : public CollisionBackend {};
class SecondBackend : public CollisionBackend {};

TEST(BackendRegistryTest, BackEndsAreFoundByKindAndNameAndListedPerKind) {
  Registry registry;
  PluginRegistrar core(registry, "core");
  core.addBackend<FirstBackend>("VoxelSkull", "native", "voxels");
  core.addBackend<FirstBackend>("TetraBrain", "native", "grid");
  PluginRegistrar plugin(registry, "meshes");
  plugin.addBackend<SecondBackend>("VoxelSkull", "meshes", "triangles");
  EXPECT_TRUE(core.errors().empty());
  EXPECT_TRUE(plugin.errors().empty());

  EXPECT_EQ(registry.backendNames("VoxelSkull"), (std::vector<std::string>{"meshes", "native"}));
  EXPECT_EQ(registry.backendNames("TetraBrain"), (std::vector<std::string>{"native"}));
  EXPECT_TRUE(registry.backendNames("Other").empty());
  ASSERT_NE(registry.findBackend("VoxelSkull", "meshes"), nullptr);
  EXPECT_EQ(registry.findBackend("VoxelSkull", "meshes")->plugin, "meshes");
  EXPECT_EQ(registry.findBackend("TetraBrain", "meshes"), nullptr) << "a name belongs to its kind";

  auto created = registry.createBackend("VoxelSkull", "meshes");
  EXPECT_NE(dynamic_cast<SecondBackend*>(created.get()), nullptr);
  EXPECT_EQ(registry.createBackend("VoxelSkull", "embree"), nullptr);
  EXPECT_EQ(registry.backends().size(), 3u);
  // Components and back-ends are apart: no component is named by a back-end.
  EXPECT_EQ(registry.find("native"), nullptr);
}

TEST(BackendRegistryTest, TheSameNameForTheSameKindTwiceIsAnErrorNamingBothPlugins) {
  Registry registry;
  PluginRegistrar first(registry, "first");
  first.addBackend<FirstBackend>("VoxelSkull", "native", "voxels");
  PluginRegistrar second(registry, "second");
  second.addBackend<SecondBackend>("VoxelSkull", "native", "again");
  ASSERT_EQ(second.errors().size(), 1u);
  EXPECT_EQ(second.errors()[0],
            "back-end 'native' of VoxelSkull is registered by both plugin 'first' and plugin 'second'");
  // The first stays.
  EXPECT_NE(dynamic_cast<FirstBackend*>(registry.createBackend("VoxelSkull", "native").get()), nullptr);
}

}  // namespace
}  // namespace trephine
