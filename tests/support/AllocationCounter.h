#pragma once
// Counting heap allocations in a test program: linking trephine_allocation_counter
// replaces the global operator new of that program with one that counts while
// counting is on (the hot loops must not allocate).
#include <cstddef>

namespace trephine::test {

void startCountingAllocations();
// Stops counting; returns the allocations since startCountingAllocations().
size_t stopCountingAllocations();

}  // namespace trephine::test
