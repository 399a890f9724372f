#pragma once
// A component whose input comes from outside the process at its own pace (a
// haptic device driven by its own servo clock): in real time, its rate
// group starts a frame as soon as that input has come, instead of at the
// clock's deadline, so the answer goes back within the device's frame. The
// clock still bounds the pace (Scheduler.h): no frame sooner than 3/4 of a
// period after the last, none later than 1.5 periods, input or not (one
// period once two frames went without input, so that a run with no device
// keeps the clock's time).
#include "framework/core/Interface.h"

namespace trephine {

class TREPHINE_INTERFACE FramePacer {
 public:
  virtual ~FramePacer();
  // Whether this component paces its group in this scene (a field's choice).
  virtual bool pacesFrames() const = 0;
  // Whether the input for the next frame has come. Polled by the group's
  // thread between frames: cheap, never blocks, never allocates. It may
  // read and judge what came (bounded work a call), so that only valid
  // input starts a frame: junk never paces the group.
  virtual bool frameInputWaiting() = 0;
};

}  // namespace trephine
