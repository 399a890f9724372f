#include "plugins/tetra_brain/MeshTetBackend.h"

#include <chrono>
#include <stdexcept>

namespace trephine::tetra {

MeshTetBackend::MeshTetBackend(std::unique_ptr<TriangleEngine> engine) : m_engine(std::move(engine)) {
  if (!m_engine) throw std::invalid_argument("MeshTetBackend needs a triangle engine");
}

std::string MeshTetBackend::owner() const {
  return "backend=\"" + std::string(m_engine->name()) + "\" of TetraBrain";
}

SphereQueryScale MeshTetBackend::scale() const {
  const double skin = m_data.options.contactDepth;
  return {skin, 0.5 * m_surface.averageEdge(), 10 * skin};
}

void MeshTetBackend::bind(const TetData& data) {
  const auto start = std::chrono::steady_clock::now();
  m_data = data;
  m_surface.build(*data.mesh, *data.topology);
  if (m_surface.block(0).triangles.empty()) throw std::runtime_error("the mesh has no boundary faces");
  m_refit = RefitPolicy(refitMargin(m_surface));
  m_engine->build(m_surface, data.options.deformable ? m_refit.margin() : 0.0);
  m_engine->counts().buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void MeshTetBackend::reserveShell(std::span<const ShellPoint> shell) {
  // Any shell: a sphere exactly, another point by point (the deepest point's
  // triangle is where the contact's force acts on the nodes) or through the
  // solid the tool describes, as the engine takes it.
  m_engine->reserveShell(shell);
}

void MeshTetBackend::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  m_engine->describeTool(shell, solid, owner());
}

void MeshTetBackend::moveNodes(const NodeFrame& frame) {
  const auto start = std::chrono::steady_clock::now();
  m_surface.moveTo(frame.nodes);  // in place: the engine reads these arrays
  m_engine->moveVertices(0, m_refit.rebuild(frame.displacementBound));
  m_following.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
}

TetContact MeshTetBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites, int32_t&) {
  TetContact result;
  const TriangleContact found = m_engine->contact(X_WT, shell);
  result.contact = found.contact;
  if (wantSites && result.contact.points > 0 && found.nearest.valid()) {
    m_site = siteAt(m_surface, found.nearest, found.nearestPoint, result.contact.penetration);
    result.sites = {&m_site, 1};
  }
  return result;
}

size_t MeshTetBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  return m_engine->broadPhase(X_WT, shell);
}

SweepResult MeshTetBackend::sweep(const SweepQuery& query) const { return m_engine->sweep(query, scale()); }

bool MeshTetBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  return m_engine->overlaps(X_WT, shell, scale());
}

std::optional<SurfaceHit> MeshTetBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                  double maxDistance) const {
  return m_engine->raycast(origin, direction, maxDistance);
}

void MeshTetBackend::reportCounters(std::vector<Counter>& counters) const {
  m_engine->reportCounters(counters);
  if (!m_data.options.deformable) return;
  counters.push_back({"refit_margin_mm", m_refit.margin()});
  m_following.report(counters);
}

}  // namespace trephine::tetra
