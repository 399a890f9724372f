#pragma once
// A component that renders with tools in hand (a ForceFeedback, through its
// proxy): which tools, in the order the `tool_in_hand` column of its samples
// counts them (0 before a tool change, 1 after), so that an exporter draws
// the one in hand in its true shape.
#include <vector>

#include "framework/core/Interface.h"
#include "framework/geometry/ShellTool.h"

namespace trephine {

class TREPHINE_INTERFACE HeldTools {
 public:
  virtual ~HeldTools();
  virtual std::vector<const ShellTool*> heldTools() const = 0;
};

}  // namespace trephine
