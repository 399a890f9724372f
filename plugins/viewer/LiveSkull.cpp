#include "plugins/viewer/LiveSkull.h"

namespace trephine::viewer {

LiveSkull::LiveSkull(const VoxelGrid& grid, const BlockedIsoSurface& fine, size_t triangles, Send send)
    : m_fine(fine), m_send(std::move(send)) {
  size_t full = 0;
  for (size_t b = 0; b < fine.blockCount(); ++b) full += fine.block(b).triangles.size();
  m_coarse = coarseIsoSurface(grid, triangles, full, fine.blocksPerAxis());
  m_pieceShown.assign(m_coarse.pieces.size(), 0);
}

void LiveSkull::sendStart() {
  const size_t offset = m_fine.blockCount();
  for (size_t b = 0; b < m_coarse.pieces.size(); ++b) {
    m_pieceShown[b] = !m_coarse.pieces[b].triangles.empty();
    if (m_pieceShown[b]) m_send(offset + b, m_coarse.pieces[b]);
  }
}

void LiveSkull::fineBlockChanged(size_t block) {
  m_send(block, m_fine.block(block));
  if (block < m_pieceShown.size() && m_pieceShown[block]) {
    m_pieceShown[block] = 0;
    m_send(m_fine.blockCount() + block, TriangleMesh{});
  }
}

}  // namespace trephine::viewer
