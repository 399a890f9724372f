#include <gtest/gtest.h>

#include <array>
#include <thread>

#include "framework/channels/Channel.h"
#include "framework/channels/TripleBuffer.h"

namespace trephine {
namespace {

TEST(TripleBufferTest, ReaderSeesTheLatestPublishedValueOnlyOnce) {
  TripleBuffer<int> buffer(0);
  EXPECT_FALSE(buffer.fetch());
  buffer.write(1);
  buffer.write(2);
  EXPECT_TRUE(buffer.fetch());
  EXPECT_EQ(buffer.read(), 2);
  EXPECT_FALSE(buffer.fetch()) << "nothing new was published";
  EXPECT_EQ(buffer.read(), 2) << "the reader keeps its value";
}

TEST(TripleBufferTest, ChannelFansOutToEveryReader) {
  Channel<double> channel;
  auto a = channel.addReader();
  auto b = channel.addReader();
  channel.publish(3.5);
  EXPECT_DOUBLE_EQ(a.latest(), 3.5);
  EXPECT_DOUBLE_EQ(b.latest(), 3.5);
}

TEST(TripleBufferTest, ReservedChannelSlotsKeepTheirCapacityForEveryReader) {
  Channel<std::vector<int>> channel;
  auto before = channel.addReader();
  channel.reserve(std::vector<int>(1000, 0));
  auto after = channel.addReader();
  const std::vector<int> value(600, 7);
  // Every slot a publication can land in already holds 1000 ints: copying 600 keeps the storage.
  for (int i = 0; i < 6; ++i) {
    channel.publish(value);
    for (auto* reader : {&before, &after}) {
      ASSERT_TRUE(reader->fetch());
      EXPECT_EQ(reader->read().size(), 600u);
      EXPECT_GE(reader->read().capacity(), 1000u) << "a slot was reallocated";
    }
  }
}

// A value written as a whole must be read as a whole: no torn reads across threads.
TEST(TripleBufferTest, ConcurrentReaderNeverSeesATornValue) {
  struct Block {
    std::array<uint64_t, 16> words{};
  };
  TripleBuffer<Block> buffer;
  constexpr uint64_t kWrites = 200000;
  std::thread writer([&] {
    for (uint64_t i = 1; i <= kWrites; ++i) {
      Block& slot = buffer.writeSlot();
      slot.words.fill(i);
      buffer.publish();
    }
  });
  uint64_t last = 0, torn = 0, backwards = 0;
  while (last < kWrites) {
    if (!buffer.fetch()) continue;
    const Block& block = buffer.read();
    for (uint64_t w : block.words) torn += w != block.words[0];
    backwards += block.words[0] < last;
    last = block.words[0];
  }
  writer.join();
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u) << "values arrive in publication order";
}

}  // namespace
}  // namespace trephine
