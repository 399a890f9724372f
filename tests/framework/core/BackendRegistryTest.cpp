// Collision back-ends in the registry: registered under a name for a kind of
// target, found and created by that pair, listed per kind; a second
// registration of the same pair is an error naming both plugins. Triangle
// engines are back-ends of every kind with an engine adapter, inside it.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

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

// An adapter of a kind: holds the engine it was made over.
class Adapter : public CollisionBackend {
 public:
  explicit Adapter(std::unique_ptr<CollisionBackend> engine) : engine(std::move(engine)) {}
  std::unique_ptr<CollisionBackend> engine;
};

TEST(BackendRegistryTest, AnEngineIsABackEndOfEveryKindWithAnAdapterInsideIt) {
  Registry registry;
  PluginRegistrar engines(registry, "engines");
  engines.addTriangleEngine<SecondBackend>("bvh", "triangles in a tree");
  PluginRegistrar skull(registry, "skull");
  skull.addBackend<FirstBackend>("VoxelSkull", "native", "voxels");
  skull.addEngineAdapter("VoxelSkull", [](std::unique_ptr<CollisionBackend> engine) {
    return std::unique_ptr<CollisionBackend>(new Adapter(std::move(engine)));
  });
  EXPECT_TRUE(engines.errors().empty() && skull.errors().empty());

  EXPECT_EQ(registry.backendNames("VoxelSkull"), (std::vector<std::string>{"bvh", "native"}));
  EXPECT_TRUE(registry.backendNames("TetraBrain").empty()) << "no adapter, no engines";
  ASSERT_NE(registry.findBackend("VoxelSkull", "bvh"), nullptr);
  EXPECT_EQ(registry.findBackend("VoxelSkull", "bvh")->plugin, "engines") << "the reference names the engine";
  EXPECT_EQ(registry.findBackend("TetraBrain", "bvh"), nullptr);
  const auto created = registry.createBackend("VoxelSkull", "bvh");
  const auto* adapter = dynamic_cast<const Adapter*>(created.get());
  ASSERT_NE(adapter, nullptr) << "the kind's adapter";
  EXPECT_NE(dynamic_cast<const SecondBackend*>(adapter->engine.get()), nullptr) << "over a new engine";
  EXPECT_EQ(registry.createBackend("TetraBrain", "bvh"), nullptr);
  EXPECT_NE(dynamic_cast<FirstBackend*>(registry.createBackend("VoxelSkull", "native").get()), nullptr);

  // A kind's own back-end of an engine's name comes first.
  skull.addBackend<FirstBackend>("VoxelSkull", "bvh", "voxels again");
  EXPECT_TRUE(skull.errors().empty()) << skull.errors().front();
  EXPECT_NE(dynamic_cast<FirstBackend*>(registry.createBackend("VoxelSkull", "bvh").get()), nullptr);
  EXPECT_EQ(registry.backendNames("VoxelSkull"), (std::vector<std::string>{"bvh", "native"})) << "listed once";

  PluginRegistrar other(registry, "other");
  other.addEngineAdapter("VoxelSkull", [](std::unique_ptr<CollisionBackend>) { return nullptr; });
  ASSERT_EQ(other.errors().size(), 1u);
  EXPECT_EQ(other.errors()[0],
            "the triangle engines' adapter of VoxelSkull is registered by both plugin 'skull' and plugin 'other'");

  // An adapter that cannot use the engine is an error naming both plugins, not a missing back-end.
  PluginRegistrar brain(registry, "brain");
  brain.addEngineAdapter("TetraBrain", [](std::unique_ptr<CollisionBackend>) { return nullptr; });
  try {
    registry.createBackend("TetraBrain", "bvh");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "back-end 'bvh' of plugin 'engines' is registered as a triangle engine, but TetraBrain's adapter "
              "(plugin 'brain') cannot use it: it is not a TriangleEngine");
  }
}

PhantomWriterEntry writer(const std::string& kind, std::vector<std::string> suffixes) {
  PhantomWriterEntry entry;
  entry.kind = kind;
  entry.suffixes = std::move(suffixes);
  return entry;
}

// Phantom writers: the output file's suffix picks one, the longer suffix of
// the same stem included (.mesh.gz), and a suffix two plugins claim is an
// error naming both.
TEST(BackendRegistryTest, APhantomFileIsWrittenByThePluginThatClaimsItsSuffix) {
  Registry registry;
  PluginRegistrar volumes(registry, "volumes");
  volumes.addPhantomWriter(writer("volume", {".mha", ".mhd"}));
  PluginRegistrar meshes(registry, "meshes");
  meshes.addPhantomWriter(writer("mesh", {".mesh", ".mesh.gz"}));
  EXPECT_TRUE(volumes.errors().empty() && meshes.errors().empty());
  ASSERT_NE(registry.phantomWriterFor("out/skull.mha"), nullptr);
  EXPECT_EQ(registry.phantomWriterFor("out/skull.mha")->plugin, "volumes");
  ASSERT_NE(registry.phantomWriterFor("brain.mesh.gz"), nullptr);
  EXPECT_EQ(registry.phantomWriterFor("brain.mesh.gz")->kind, "mesh");
  EXPECT_EQ(registry.phantomWriterFor("brain.vtk"), nullptr);
  EXPECT_EQ(registry.phantomWriterFor(".mha"), nullptr) << "a suffix alone is no file name";

  PluginRegistrar again(registry, "again");
  again.addPhantomWriter(writer("volume", {".mhd"}));
  ASSERT_EQ(again.errors().size(), 1u);
  EXPECT_EQ(again.errors()[0], "phantom files '.mhd' are written by both plugin 'volumes' ('.mhd') and plugin 'again'");
  PluginRegistrar gz(registry, "gz");
  gz.addPhantomWriter(writer("gzip", {".gz"}));
  ASSERT_EQ(gz.errors().size(), 1u) << "'.gz' ends '.mesh.gz': a .mesh.gz file would be claimed twice";
  EXPECT_EQ(registry.phantomWriters().size(), 2u);
}

// A service is found by its interface's name and points at the interface part
// of the object (not at the start of a class with several bases); a second
// provider is an error naming both plugins.
struct Greeter {
  static constexpr std::string_view kTypeName = "Greeter";
  virtual ~Greeter() = default;
  virtual int greet() const = 0;
};
struct Padding {
  virtual ~Padding() = default;
  double unused[4] = {};
};
struct PaddedGreeter final : Padding, Greeter {
  int greet() const override { return 42; }
};

TEST(BackendRegistryTest, AServiceIsFoundByItsInterfaceAndProvidedOnce) {
  Registry registry;
  EXPECT_EQ(registry.service<Greeter>(), nullptr);
  PluginRegistrar first(registry, "one");
  first.addService<Greeter>(std::make_shared<PaddedGreeter>());
  EXPECT_TRUE(first.errors().empty());
  ASSERT_NE(registry.service<Greeter>(), nullptr);
  EXPECT_EQ(registry.service<Greeter>()->greet(), 42);
  EXPECT_EQ(registry.findService("Greeter")->plugin, "one");
  PluginRegistrar second(registry, "two");
  second.addService<Greeter>(std::make_shared<PaddedGreeter>());
  ASSERT_EQ(second.errors().size(), 1u);
  EXPECT_NE(second.errors()[0].find("'one'"), std::string::npos) << second.errors()[0];
  EXPECT_NE(second.errors()[0].find("'two'"), std::string::npos) << second.errors()[0];
}

}  // namespace
}  // namespace trephine
