#pragma once
// A tetrahedral mesh that another component deforms (TetraBrain): the FEM
// follows it and publishes its node positions, an exporter draws it. The
// data crossing between them is in framework/data/MeshDeformation.h and
// travels on the mesh's and the deformer's channels.
#include <optional>
#include <string>
#include <string_view>

#include "framework/channels/ChangeQueue.h"
#include "framework/core/Interface.h"
#include "framework/data/MeshDeformation.h"
#include "framework/data/TetMesh.h"

namespace trephine {

class ChannelHub;
class Component;

class TREPHINE_INTERFACE DeformableMesh {
 public:
  static constexpr std::string_view kTypeName = "DeformableMesh";
  virtual ~DeformableMesh();

  // The mesh at rest (mm, world), valid from the end of the mesh's init().
  virtual const TetMesh& mesh() const = 0;
  // Called by the deformer in its init(): from then on the mesh takes the
  // NodePositions `deformer` publishes on kNodePositionsChannel at the start
  // of each haptic frame, and publishes NodeForces on its own
  // kNodeForcesChannel. Returns what is wrong (a second deformer, ...).
  virtual std::optional<std::string> followDeformation(const Component& deformer, ChannelHub& channels) = 0;
  // The component that deforms this mesh, or null.
  virtual const Component* deformer() const = 0;
  // A reader of the tetrahedra a resection removes (by index in mesh()), in
  // its init: each is pushed once to the reader's own queue, which has room
  // for every tetrahedron. Nothing is pushed to a mesh no tool resects.
  virtual ChangeQueue<int32_t>& subscribeRemovals() = 0;
};

}  // namespace trephine
