// The program the tests' precompiled header is built for (tests/CMakeLists.txt):
// every test program reuses its header, none runs this one.
#include <gtest/gtest.h>
