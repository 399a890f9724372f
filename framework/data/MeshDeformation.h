#pragma once
// What crosses between a deformable tetrahedral mesh (DeformableMesh) and
// the component that deforms it, through the scheduler's channels (never
// shared state):
//  - the deformer publishes NodePositions on its "node_positions" channel,
//    which the mesh it deforms reads at the start of each haptic frame;
//  - the mesh publishes NodeForces on its "node_forces" channel: the
//    reaction of the tool's force on the mesh nodes, computed only when a
//    component reads it.
#include <cmath>
#include <cstdint>
#include <vector>

#include "framework/math/Math.h"

namespace trephine {

inline constexpr const char* kNodePositionsChannel = "node_positions";
inline constexpr const char* kNodeForcesChannel = "node_forces";
inline constexpr const char* kElementStressChannel = "element_stress";

struct NodePositions {
  uint64_t step = 0;             // the producer's tick count; 0 before the first
  std::vector<Vec3> positions;   // mm, world, one per mesh node
  double displacementBound = 0;  // mm, no node is farther than this from its rest position
  // mm, no node moved farther than this since the producer's previous step
  // (step - 1); infinite when unknown. Lets a reader that follows every step
  // bound the drift from an earlier shape without visiting every node.
  double largestMove = INFINITY;
  // Nodes moved since the producer's previous step (`allMoved`: every node),
  // for the thesis's refresh of only the moved tetrahedra's boxes.
  bool allMoved = true;
  std::vector<int32_t> movedNodes;
  // Times the producer gave up its shape and started again from rest (a
  // diverged FEM reset): a reader that sees it grow knows the shape jumped,
  // and a tool on it lets go of its contact.
  uint64_t resets = 0;
};

struct NodeForce {
  int32_t node = -1;
  Vec3 force = Vec3::Zero();  // N, on the mesh node
};

struct NodeForces {
  double t = 0;                // s, haptic frame that produced them
  // The deformation's reset count (NodePositions::resets) the contact was
  // measured after: forces measured on a shape from before a reset belong to
  // a contact that is gone, and the deformation drops them.
  uint64_t resetsSeen = 0;
  // One entry per node the contact touches. The publisher's channel slots are
  // reserved at 4 nodes per shell point, so a copy never allocates and costs
  // only the entries in use.
  std::vector<NodeForce> forces;
};

// The stress of each element of a deformable mesh, which a deformer that
// computes stresses (the TLED FEM) publishes on its "element_stress" channel
// only while a component reads it (a viewer colouring the brain by stress),
// and then at most every so often: the element loop never pays for it.
struct ElementStress {
  double t = 0;  // s, the deformer's time when the sweep over the elements ended
  // kPa, one per tetrahedron in the mesh's order: the von Mises equivalent
  // of the Cauchy (true) stress, sqrt(3/2 s:s) with s its deviatoric part.
  std::vector<float> vonMises;
};

}  // namespace trephine
