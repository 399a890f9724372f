#pragma once
// What a TetraBrain keeps while tools resect it (its Resection component
// enabled it): what remains of the mesh, the removal law and its totals, the
// tetrahedra due to go at the start of the next frame, and a record of the
// totals over time (resection.csv). Sized at construction and by
// reserveRecord(): the haptic frame's calls (act, applyPending) never allocate.
#include <cstdint>
#include <span>
#include <vector>

#include "framework/data/RemainingMesh.h"
#include "plugins/tetra_brain/TissueRemoval.h"

namespace trephine::tetra {

class BrainResection {
 public:
  BrainResection(const TetMesh& mesh, const TetTopology& topology, const TissueTable& tissues);

  // Room for one record row a millisecond of a run of `duration` s. Allocates.
  void reserveRecord(double duration);
  // One frame's responses (the haptic frame's respond): the law's energy,
  // the tetrahedra due to go, a record row. Whether a tool touched critical
  // tissue this frame.
  bool act(double t, std::span<const ContactResponse> responses);
  // Tetrahedra due to go at the next removeNext(), beside what act() queues
  // (a tool of another kind, tests). Indices out of range are skipped.
  void queue(std::span<const int32_t> tets);
  // The start of a frame: removes the tetrahedra due to go, then the pieces
  // those removals cut loose (call until it returns an empty change: each
  // change's spans last until the next call, so its readers take it first).
  // A piece is loose when its tetrahedra, joined by faces, number fewer than
  // loosePieceLimit() and none holds to the rest: it would hang by an edge or a
  // node, or float, in the FEM; the aspirator takes it with the rest. So
  // do fragments: a tetrahedron held by one face at most (a flap), and the
  // tetrahedra of a node that kSpikeUse of them at most hold (a spike's
  // tip, a fin one element thick): a tool's force drags such a node through
  // its few elements, which invert.
  RemainingMesh::Change removeNext();
  // kLoosePiece tetrahedra, or an eighth of a smaller mesh.
  static constexpr size_t kLoosePiece = 256;
  size_t loosePieceLimit() const { return m_pieceLimit; }
  static constexpr uint32_t kSpikeUse = 2;
  uint64_t loosePieces() const { return m_loosePieces; }
  uint64_t looseTets() const { return m_looseTets; }
  uint64_t fragments() const { return m_fragments; }

  const RemainingMesh& remaining() const { return m_remaining; }
  // Whether a node is on the surface now (a boundary face of what remains holds it).
  bool onSurface(int32_t node) const { return m_surfaceFaces[size_t(node)] > 0; }
  // Boundary faces of what remains.
  size_t boundaryFaces() const { return m_boundaryFaces; }
  const TissueRemoval& law() const { return m_law; }
  const ResectionTotals& totals() const { return m_law.totals(); }
  // The record: rows of recordColumns() values (t s, removed mm^3, blood ml,
  // critical contact s, then removed mm^3 per tissue).
  size_t recordColumns() const { return 4 + m_law.totals().removed_mm3.size(); }
  std::span<const double> recordRows() const { return m_rows; }
  uint64_t droppedRows() const { return m_droppedRows; }

 private:
  RemainingMesh m_remaining;
  TissueRemoval m_law;
  // Gathers the tetrahedra of the loose pieces around the last removal into m_pending.
  void findLoosePieces();

  const TetMesh* m_mesh = nullptr;
  const TetTopology* m_topology;
  std::vector<int32_t> m_pending;  // capacity: every tetrahedron
  std::vector<int32_t> m_around;   // alive tetrahedra beside the last removal (capacity: every face)
  std::vector<int32_t> m_piece;    // a flood fill's tetrahedra (capacity: m_pieceLimit)
  size_t m_pieceLimit = 0;
  std::vector<uint32_t> m_surfaceFaces;  // per node: boundary faces holding it now
  size_t m_boundaryFaces = 0;
  std::vector<uint32_t> m_seen;    // per tetrahedron: the search that reached it
  std::vector<uint8_t> m_holds;    // per tetrahedron: that search found it holds to the rest
  uint32_t m_search = 0;
  uint64_t m_loosePieces = 0, m_looseTets = 0, m_fragments = 0;
  std::vector<uint32_t> m_nodeTetStart;  // node -> its tetrahedra (rows)
  std::vector<int32_t> m_nodeTets;
  std::vector<int32_t> m_spikeNodes;     // nodes the last removal left held by kSpikeUse tetrahedra at most
  std::vector<double> m_rows;      // capacity: reserveRecord()
  double m_lastRow = -1e300;
  uint64_t m_droppedRows = 0;
};

}  // namespace trephine::tetra
