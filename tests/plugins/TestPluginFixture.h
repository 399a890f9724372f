#pragma once
// Tests that load the test plugins (tests/plugins/test_plugins), which are
// built into their own directory and found through TREPHINE_PLUGIN_PATH.
#include <gtest/gtest.h>

#include <cstdlib>

class TestPluginFixture : public testing::Test {
 protected:
  void SetUp() override { setenv("TREPHINE_PLUGIN_PATH", TREPHINE_TEST_PLUGIN_DIR, 1); }
  void TearDown() override { unsetenv("TREPHINE_PLUGIN_PATH"); }
};
