// MadeOnce: a value made once per key and copied after, within its capacity
// and size bound; a failure to make one is not kept.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "framework/core/MadeOnce.h"

namespace trephine {
namespace {

size_t lengthOf(const std::string& s) { return s.size(); }

TEST(MadeOnceTest, MakesAKeysValueOnceAndCopiesItAfter) {
  MadeOnce<std::string> made(4, 100, lengthOf);
  int makes = 0;
  const auto make = [&] { return std::string("value ") + std::to_string(++makes); };
  EXPECT_EQ(made.get("a", make), "value 1");
  std::string copy = made.get("a", make);
  EXPECT_EQ(copy, "value 1");
  copy += " changed";  // the caller's copy: the kept one does not change
  EXPECT_EQ(made.get("a", make), "value 1");
  EXPECT_EQ(made.get("b", make), "value 2");
  EXPECT_EQ(makes, 2);
}

TEST(MadeOnceTest, KeepsTheMostRecentlyUsedWithinItsCapacity) {
  MadeOnce<std::string> made(2, 100, lengthOf);
  int makes = 0;
  const auto make = [&] { return std::to_string(++makes); };
  made.get("a", make);  // 1
  made.get("b", make);  // 2
  made.get("a", make);  // kept; b is now the least recently used
  made.get("c", make);  // 3, b goes
  EXPECT_EQ(makes, 3);
  EXPECT_EQ(made.get("a", make), "1");
  EXPECT_EQ(made.get("b", make), "4") << "made again";
  EXPECT_EQ(makes, 4);
}

TEST(MadeOnceTest, AValueLargerThanTheBoundIsMadeEachTime) {
  MadeOnce<std::string> made(4, 3, lengthOf);
  int makes = 0;
  const auto large = [&] { return std::string(4, char('0' + ++makes)); };
  EXPECT_EQ(made.get("large", large), "1111");
  EXPECT_EQ(made.get("large", large), "2222");
  const auto small = [&] { return std::string(3, char('0' + ++makes)); };
  EXPECT_EQ(made.get("small", small), "333");
  EXPECT_EQ(made.get("small", small), "333");
}

TEST(MadeOnceTest, AFailureReachesTheCallerAndIsNotKept) {
  MadeOnce<std::string> made(4, 100, lengthOf);
  EXPECT_THROW(made.get("a", []() -> std::string { throw std::runtime_error("cannot"); }), std::runtime_error);
  EXPECT_EQ(made.get("a", [] { return std::string("made"); }), "made");
}

TEST(MadeOnceTest, ThreadsAskingAtOnceAllGetTheValue) {
  MadeOnce<std::string> made(4, 100, lengthOf);
  std::vector<std::thread> threads;
  std::vector<std::string> got(8);
  for (size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] { got[i] = made.get(i % 2 ? "odd" : "even", [&] { return std::string(i % 2 ? "o" : "e"); }); });
  for (std::thread& t : threads) t.join();
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], i % 2 ? "o" : "e");
}

}  // namespace
}  // namespace trephine
