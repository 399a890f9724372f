#include "framework/formats/mesh/MeditWriter.h"

#include <zlib.h>

#include <charconv>
#include <cmath>
#include <string_view>

namespace trephine::formats {

namespace {

// Text is handed to the file (or to zlib) in pieces of about this size, so a
// million-tetrahedron mesh never exists twice in memory.
constexpr size_t kFlushBytes = size_t(1) << 20;

// Buffers text and passes it to the file, through a gzip stream when asked.
class MeshTextOutput {
 public:
  MeshTextOutput(const OutputPath& output, bool gzip) : m_file(output), m_gzip(gzip) {
    const std::filesystem::path file = output.path();
    m_buffer.reserve(kFlushBytes + 256);
    if (!m_gzip) return;
    // windowBits 15 + 16: a gzip wrapper, which the readers (and gunzip) expect of a .gz file.
    if (deflateInit2(&m_zlib, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
      throw TetMeshWriteError(file, "cannot initialise zlib");
    m_compressed.resize(size_t(1) << 16);
  }
  ~MeshTextOutput() {
    if (m_gzip) deflateEnd(&m_zlib);
  }
  MeshTextOutput(const MeshTextOutput&) = delete;
  MeshTextOutput& operator=(const MeshTextOutput&) = delete;

  void text(std::string_view text) { m_buffer += text; }

  // Shortest form that reads back to exactly the same double.
  void real(double value) {
    char digits[32];
    const auto result = std::to_chars(digits, digits + sizeof digits, value);
    m_buffer.append(digits, result.ptr);
  }

  void integer(int64_t value) {
    char digits[24];
    const auto result = std::to_chars(digits, digits + sizeof digits, value);
    m_buffer.append(digits, result.ptr);
  }

  // Called after each record: writes once enough text has gathered.
  void endRecord() {
    m_buffer += '\n';
    if (m_buffer.size() >= kFlushBytes) flush(Z_NO_FLUSH);
  }

  void commit() {
    flush(Z_FINISH);
    m_file.commit();
  }

 private:
  void flush(int zlibFlush) {
    if (!m_gzip) {
      m_file.write(m_buffer.data(), m_buffer.size());
      m_buffer.clear();
      return;
    }
    m_zlib.next_in = reinterpret_cast<Bytef*>(m_buffer.data());
    m_zlib.avail_in = static_cast<uInt>(m_buffer.size());
    int code = Z_OK;
    do {
      m_zlib.next_out = reinterpret_cast<Bytef*>(m_compressed.data());
      m_zlib.avail_out = static_cast<uInt>(m_compressed.size());
      code = deflate(&m_zlib, zlibFlush);
      if (code == Z_STREAM_ERROR) throw TetMeshWriteError(m_file.path(), "zlib compression failed");
      m_file.write(m_compressed.data(), m_compressed.size() - m_zlib.avail_out);
    } while (m_zlib.avail_out == 0 || (zlibFlush == Z_FINISH && code != Z_STREAM_END));
    m_buffer.clear();
  }

  AtomicFile m_file;
  bool m_gzip;
  z_stream m_zlib{};
  std::string m_buffer;
  std::string m_compressed;
};

// The same limits the readers apply, checked before any file is created.
void checkWritable(const TetMesh& mesh, const std::filesystem::path& file) {
  if (mesh.tets.empty()) throw TetMeshWriteError(file, "the mesh has no tetrahedra");
  if (!mesh.labels.empty() && mesh.labels.size() != mesh.tets.size())
    throw TetMeshWriteError(file, std::to_string(mesh.labels.size()) + " labels for " +
                                      std::to_string(mesh.tets.size()) +
                                      " tetrahedra (expected one per tetrahedron, or none)");
  for (size_t n = 0; n < mesh.nodes.size(); ++n)
    if (!mesh.nodes[n].allFinite())
      throw TetMeshWriteError(file, "node " + std::to_string(n) + " has a non-finite coordinate");
  const auto nodeCount = int64_t(mesh.nodes.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (const int32_t corner : mesh.tets[t])
      if (corner < 0 || corner >= nodeCount)
        throw TetMeshWriteError(file, "tetrahedron " + std::to_string(t) + " refers to node " + std::to_string(corner) +
                                          ", but the mesh has nodes 0 to " + std::to_string(nodeCount - 1));
}

}  // namespace

void writeMeditMesh(const TetMesh& mesh, const OutputPath& output) {
  const std::filesystem::path file = output.path();
  checkWritable(mesh, file);
  MeshTextOutput out(output, file.extension() == ".gz");
  out.text("MeshVersionFormatted 2");
  out.endRecord();
  out.text("Dimension 3");
  out.endRecord();
  out.text("Vertices ");
  out.integer(int64_t(mesh.nodes.size()));
  out.endRecord();
  for (const Vec3& node : mesh.nodes) {
    for (int axis = 0; axis < 3; ++axis) {
      out.real(node[axis]);
      out.text(" ");
    }
    out.text("0");
    out.endRecord();
  }
  out.text("Tetrahedra ");
  out.integer(int64_t(mesh.tets.size()));
  out.endRecord();
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    for (const int32_t corner : mesh.tets[t]) {
      out.integer(int64_t(corner) + 1);  // Medit counts from 1
      out.text(" ");
    }
    out.integer(mesh.labels.empty() ? 0 : mesh.labels[t]);
    out.endRecord();
  }
  out.text("End");
  out.endRecord();
  out.commit();
}

}  // namespace trephine::formats
