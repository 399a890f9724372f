#pragma once
// What a VtkExporter streams to the live view (`trephine run --realtime
// --view PORT`): the same parts as its files, as WebSocket messages the
// browser viewer (plugins/viewer/web/src/live.js) reads. All little-endian,
// 4-byte aligned, each starting with a uint32 type:
//   1 tool    u32 contact (1: the contact point follows), f64 t (s),
//             f32 device[3], proxy[3], force[3] (mm, N), f32 tool radius
//             (mm), penetration (mm), contact point[3] (mm)
//   2 nodes   u32 node count n, f64 t, f32 positions[3n] (mm)
//   3 cells   u32 tetrahedron count m, i32 corners[4m]
//   4 block   u32 block, u32 point count p, u32 triangle count q,
//             f32 points[3p] (mm), u32 corners[3q]
//   5 tool's surface  u32 point count p, u32 triangle count q, f32
//             points[3p] (mm, in the world), u32 corners[3q]: the tool in
//             hand in its true shape (part "toolshape")
// The parts are in the manifest the server gives the page. The skull's
// blocks come from LiveSkull: a coarse isosurface at the start, the drilled
// region at full resolution; an empty block message removes a block. Messages are keyed (LiveServer): a
// slow browser gets the latest tool, nodes and each block's latest surface.
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "framework/data/TriangleBlocks.h"
#include "framework/math/Math.h"

namespace trephine::viewer {

class LiveServer;

class LiveStream {
 public:
  // Throws std::runtime_error when the viewer was not built or the port
  // cannot be had.
  LiveStream(int port, const std::string& name, double duration, const std::vector<std::string>& partNames,
             const std::vector<std::string>& partKinds);
  ~LiveStream();

  int port() const;
  // Its counters: clients, messages skipped, requests refused, timeouts.
  const LiveServer& server() const { return *m_server; }

  void sendCells(std::span<const std::array<int32_t, 4>> tets);
  void sendNodes(double t, std::span<const Vec3> nodes);
  void sendTool(double t, const Vec3& device, const Vec3& proxy, const Vec3& force, double radius,
                double penetration, const std::optional<Vec3>& contact);
  void sendSkullBlock(size_t block, const TriangleMesh& mesh);
  void sendToolSurface(std::span<const Vec3> points, std::span<const std::array<int32_t, 3>> triangles);

 private:
  std::unique_ptr<LiveServer> m_server;
  std::string m_message;  // reused
};

}  // namespace trephine::viewer
