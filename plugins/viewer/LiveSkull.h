#pragma once
// The skull in the live view: at the start, the coarse stand-in for its
// isosurface (CoarseIsoSurface: at most `triangles`, in pieces by block);
// where the drill changes a block, that block's piece goes and the block
// comes at full resolution, as in the recorded files. Coarse piece b travels as block fineBlocks + b of the
// stream's messages (an empty one removes it).
#include <cstdint>
#include <functional>
#include <vector>

#include "framework/data/CoarseIsoSurface.h"
#include "framework/data/IsoSurface.h"

namespace trephine::viewer {

class LiveSkull {
 public:
  // Sends a block's surface (an empty mesh: the block is gone).
  using Send = std::function<void(size_t block, const TriangleMesh& mesh)>;

  // `fine`: the full-resolution blocks of `grid` (kept current by the caller).
  LiveSkull(const VoxelGrid& grid, const BlockedIsoSurface& fine, size_t triangles, Send send);

  // Sends the coarse pieces.
  void sendStart();
  // Fine block `block` changed: its coarse piece goes, the block comes.
  void fineBlockChanged(size_t block);

  int factor() const { return m_coarse.factor; }
  size_t coarseTriangles() const { return m_coarse.triangles; }
  const ProjectionCounts& projection() const { return m_coarse.projection; }

 private:
  const BlockedIsoSurface& m_fine;
  CoarseIsoSurface m_coarse;
  std::vector<uint8_t> m_pieceShown;  // per fine block: its coarse piece is drawn
  Send m_send;
};

}  // namespace trephine::viewer
