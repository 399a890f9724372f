#pragma once
// Assertions on loader diagnostics: the exact "file:line:col: error: " prefix
// plus a key part of the message; on failure every diagnostic is printed.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/TestSupport.h"

namespace trephine::test {

// Passes when some diagnostic reads "<location>: error: ..." and contains `text`.
inline ::testing::AssertionResult hasError(const Diagnostics& diagnostics, const std::string& location,
                                           const std::string& text) {
  const std::string prefix = location + ": error: ";
  for (const Diagnostic& d : diagnostics.all()) {
    const std::string line = d.str();
    if (line.starts_with(prefix) && line.find(text) != std::string::npos) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "expected an error starting \"" << prefix << "\" containing \"" << text
                                       << "\"; got:\n"
                                       << messages(diagnostics);
}

// Passes when no diagnostic contains `text`.
inline ::testing::AssertionResult mentionsNowhere(const Diagnostics& diagnostics, const std::string& text) {
  if (messages(diagnostics).find(text) == std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "unexpected \"" << text << "\" in:\n" << messages(diagnostics);
}

// Loads `xml` as "inline.xml" (or `fileName`) and returns what the load reported;
// the load is expected to fail.
inline Diagnostics loadFailure(const std::string& xml, const SimulationOptions& options = {},
                               const std::string& fileName = "inline.xml") {
  Diagnostics diagnostics;
  auto simulation = loadScene(xml, diagnostics, options, fileName);
  EXPECT_EQ(simulation, nullptr) << "the scene loaded although it should not";
  EXPECT_TRUE(diagnostics.hasErrors());
  return diagnostics;
}

}  // namespace trephine::test
