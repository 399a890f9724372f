// VisitStamps: each item is a first visit once per query, every query starts
// clean, and the marks survive the 32-bit stamp wrapping around.
#include <gtest/gtest.h>

#include "plugins/tetra_brain/VisitStamps.h"

namespace trephine::tetra {
namespace {

TEST(VisitStamps, EachItemIsAFirstVisitOncePerQuery) {
  VisitStamps visits;
  visits.resize(4);
  visits.begin();
  EXPECT_TRUE(visits.firstVisit(2));
  EXPECT_FALSE(visits.firstVisit(2));
  EXPECT_TRUE(visits.firstVisit(0));
  visits.begin();  // a new query: nothing is marked
  EXPECT_TRUE(visits.firstVisit(2));
  EXPECT_TRUE(visits.firstVisit(0));
  EXPECT_FALSE(visits.firstVisit(0));
}

TEST(VisitStamps, AWrappingStampClearsTheOldMarks) {
  // Item 1 is marked by the first query (stamp 1); 2^32 - 1 queries later
  // the stamp wraps through 0 back to 1, where the old mark must not count.
  VisitStamps visits;
  visits.resize(3);
  visits.begin();
  EXPECT_TRUE(visits.firstVisit(1));
  for (uint64_t q = 0; q < 0xFFFFFFFFull; ++q) visits.begin();
  EXPECT_TRUE(visits.firstVisit(1));
  EXPECT_FALSE(visits.firstVisit(1));
}

}  // namespace
}  // namespace trephine::tetra
