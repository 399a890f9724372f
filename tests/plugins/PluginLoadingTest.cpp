// Plugin loading: search path, clashes, broken libraries.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "tests/plugins/TestPluginFixture.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using PluginLoadingTest = TestPluginFixture;

TEST_F(PluginLoadingTest, TwoPluginsRegisteringOneTypeIsAnErrorNamingBoth) {
  Diagnostics d;
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="test_duplicate"/>
</Node>)",
                                    d);
  EXPECT_FALSE(simulation);
  EXPECT_NE(test::messages(d).find(
                "inline.xml:3:3: error: component 'SphereTool' is registered by both plugin 'haptics' and plugin "
                "'test_duplicate'"),
            std::string::npos)
      << test::messages(d);
}

TEST_F(PluginLoadingTest, ALibraryWithoutEntryPointIsReported) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene("<Node name=\"root\">\n  <RequiredPlugin name=\"test_no_entry\"/>\n</Node>", d));
  EXPECT_NE(test::messages(d).find("inline.xml:2:3: error: plugin 'test_no_entry' (" TREPHINE_TEST_PLUGIN_DIR
                                   "/trephine_test_no_entry.so) has no trephine_register_plugin entry point"),
            std::string::npos)
      << test::messages(d);
}

TEST_F(PluginLoadingTest, AFileThatIsNotALibraryFailsToLoadWithTheReason) {
  test::TempDir dir;
  dir.write("trephine_garbage.so", "not an ELF file");
  setenv("TREPHINE_PLUGIN_PATH", dir.path().c_str(), 1);
  Diagnostics d;
  EXPECT_FALSE(test::loadScene("<Node name=\"root\">\n  <RequiredPlugin name=\"garbage\"/>\n</Node>", d));
  const std::string text = test::messages(d);
  EXPECT_NE(text.find("inline.xml:2:3: error: plugin 'garbage' failed to load from " +
                      (dir / "trephine_garbage.so").string()),
            std::string::npos)
      << text;
}

TEST_F(PluginLoadingTest, PluginPathDirectoriesComeFirstAndListAvailablePlugins) {
  PluginLoader loader;
  ASSERT_FALSE(loader.searchPath().empty());
  EXPECT_EQ(loader.searchPath().front(), TREPHINE_TEST_PLUGIN_DIR);
  const auto available = loader.available();
  for (const char* name : {"analytic", "haptics", "test_duplicate", "test_no_entry"})
    EXPECT_NE(std::find(available.begin(), available.end(), name), available.end()) << name;
}

TEST(RegistryTest, RegistersEachTypeOnce) {
  Registry registry;
  PluginRegistrar first(registry, "one"), second(registry, "two");
  first.add<Component>("Thing", "first");
  second.add<Component>("Thing", "second");
  ASSERT_EQ(second.errors().size(), 1u);
  EXPECT_EQ(second.errors()[0], "component 'Thing' is registered by both plugin 'one' and plugin 'two'");
  EXPECT_EQ(registry.find("Thing")->plugin, "one");
}

}  // namespace
}  // namespace trephine
