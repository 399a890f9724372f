#pragma once
// Preallocated per-frame record of the haptic loop. The loop writes one frame
// per tick without allocating; the run writes the log to trace.csv and derives
// the summary's `haptics` figures from it after the run (or after an interrupt).
#include <cstddef>
#include <vector>

#include "framework/logs/HapticFrame.h"

namespace trephine {

struct HapticStats {
  size_t frames = 0;
  size_t contactFrames = 0;
  double forceMax = 0, forceMean = 0;              // N, |F|
  double forceStepMax = 0, forceStepP99 = 0;       // N, |F_k - F_{k-1}|
  double penetrationMax = 0, penetrationMean = 0;  // mm, over contact frames
  size_t nanFrames = 0;
  size_t proxyInsideFrames = 0;
  size_t droppedFrames = 0;  // frames beyond the preallocated capacity
};

class HapticFrameLog {
 public:
  explicit HapticFrameLog(size_t capacity = 0) { reserve(capacity); }
  void reserve(size_t capacity) { m_frames.resize(capacity); }

  // Hot path: constant time, no allocation. Frames past the capacity are counted, not stored.
  void record(const HapticFrame& frame) {
    if (m_size < m_frames.size()) {
      m_frames[m_size++] = frame;
    } else {
      ++m_dropped;
    }
  }

  size_t size() const { return m_size; }
  size_t dropped() const { return m_dropped; }
  const HapticFrame& operator[](size_t i) const { return m_frames[i]; }

  HapticStats stats() const;

 private:
  std::vector<HapticFrame> m_frames;
  size_t m_size = 0;
  size_t m_dropped = 0;
};

}  // namespace trephine
