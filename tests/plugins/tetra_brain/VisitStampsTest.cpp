// VisitStamps: each item is a first visit once per query, every query starts
// clean, and resizing (a rebuilt mesh) forgets every mark.
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

TEST(VisitStamps, ResizingForgetsEveryMark) {
  VisitStamps visits;
  visits.resize(2);
  visits.begin();
  EXPECT_TRUE(visits.firstVisit(1));
  visits.resize(3);  // a rebuilt mesh: stamps restart, no old mark may count
  visits.begin();
  EXPECT_TRUE(visits.firstVisit(1));
  EXPECT_TRUE(visits.firstVisit(2));
  EXPECT_FALSE(visits.firstVisit(2));
}

}  // namespace
}  // namespace trephine::tetra
