#include "framework/runtime/RunViewer.h"

namespace trephine {

RunViewer::~RunViewer() = default;  // the key function: the type information lives here

}  // namespace trephine
