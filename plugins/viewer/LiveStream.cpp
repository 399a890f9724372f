#include "plugins/viewer/LiveStream.h"

#include <cstring>
#include <sstream>
#include <stdexcept>

#include "framework/runtime/JsonWriter.h"
#include "plugins/viewer/LiveServer.h"
#include "plugins/viewer/ViewerAssets.h"

namespace trephine::viewer {

namespace {

template <class T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

void putVec(std::string& out, const Vec3& v) {
  for (int a = 0; a < 3; ++a) put(out, float(v[a]));
}

std::string blockMessage(size_t block, std::span<const Vec3> points, std::span<const std::array<int32_t, 3>> triangles) {
  std::string out;
  out.reserve(16 + 12 * points.size() + 12 * triangles.size());
  put(out, uint32_t(4));
  put(out, uint32_t(block));
  put(out, uint32_t(points.size()));
  put(out, uint32_t(triangles.size()));
  for (const Vec3& p : points) putVec(out, p);
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) put(out, uint32_t(t[k]));
  return out;
}

}  // namespace

LiveStream::LiveStream(int port, const std::string& name, double duration, const std::vector<std::string>& partNames,
                       const std::vector<std::string>& partKinds) {
  const std::filesystem::path assets = findViewerAssets();
  if (assets.empty())
    throw std::runtime_error("the live view needs the browser viewer built (Node.js and npm: tools/setup)");
  std::ostringstream manifest;
  manifest << "window.trephineRun = ";
  JsonWriter json(manifest);
  json.beginObject().field("name", name).field("live", true).field("end", duration);
  json.key("parts").beginArray();
  for (size_t i = 0; i < partNames.size(); ++i)
    json.beginObject().field("name", partNames[i]).field("kind", partKinds[i]).key("states").beginArray().endArray()
        .endObject();
  json.endArray().key("frames").beginArray().endArray().key("files").beginObject().endObject();
  json.key("plots").null().endObject();
  manifest << ";\n";
  m_server = std::make_unique<LiveServer>(port, assets, manifest.str());
}

LiveStream::~LiveStream() = default;

int LiveStream::port() const { return m_server->port(); }

void LiveStream::sendCells(std::span<const std::array<int32_t, 4>> tets) {
  std::string out;
  put(out, uint32_t(3));
  put(out, uint32_t(tets.size()));
  for (const auto& t : tets)
    for (int k = 0; k < 4; ++k) put(out, t[k]);
  m_server->send("cells", std::move(out), true);
}

void LiveStream::sendNodes(double t, std::span<const Vec3> nodes) {
  m_message.clear();
  put(m_message, uint32_t(2));
  put(m_message, uint32_t(nodes.size()));
  put(m_message, t);
  for (const Vec3& p : nodes) putVec(m_message, p);
  m_server->send("nodes", m_message, true);
}

void LiveStream::sendTool(double t, const Vec3& device, const Vec3& proxy, const Vec3& force, double radius,
                          double penetration, const std::optional<Vec3>& contact) {
  m_message.clear();
  put(m_message, uint32_t(1));
  put(m_message, uint32_t(contact ? 1 : 0));
  put(m_message, t);
  putVec(m_message, device);
  putVec(m_message, proxy);
  putVec(m_message, force);
  put(m_message, float(radius));
  put(m_message, float(penetration));
  putVec(m_message, contact.value_or(Vec3::Zero()));
  m_server->send("tool", m_message, true);
}

void LiveStream::sendSkullBlock(size_t block, const TriangleMesh& mesh) {
  m_server->send("block/" + std::to_string(block), blockMessage(block, mesh.vertices, mesh.triangles), true);
}

void LiveStream::sendToolSurface(std::span<const Vec3> points, std::span<const std::array<int32_t, 3>> triangles) {
  m_message.clear();
  put(m_message, uint32_t(5));
  put(m_message, uint32_t(points.size()));
  put(m_message, uint32_t(triangles.size()));
  for (const Vec3& p : points) putVec(m_message, p);
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) put(m_message, uint32_t(t[k]));
  m_server->send("toolshape", m_message, true);
}

}  // namespace trephine::viewer
