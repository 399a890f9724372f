#include "framework/formats/vtk/VtkXml.h"

#include <bit>
#include <cmath>
#include <cstring>

#include "framework/formats/encoding/Deflate.h"
#include "framework/core/AtomicFile.h"
#include "framework/core/Strings.h"

namespace trephine::formats {

namespace {

static_assert(std::endian::native == std::endian::little, "the files say byte_order=\"LittleEndian\"");

constexpr size_t kBlockBytes = 32768;
// zlib level 1: a frame of a 20,000-tetrahedron brain deflates in a few ms
// (level 6 took 30 ms, most of an exporter's 33 ms period at 30 Hz) for
// files about 15% larger.
constexpr int kLevel = 1;

// An array as VTK appends it: a header (block count, block size, size of the
// last block, each block's compressed size; UInt64) and the zlib blocks.
std::string packed(std::span<const uint8_t> bytes) {
  const uint64_t blocks = bytes.empty() ? 0 : (bytes.size() + kBlockBytes - 1) / kBlockBytes;
  const uint64_t last = bytes.empty() ? 0 : bytes.size() - (blocks - 1) * kBlockBytes;
  std::vector<std::string> compressed;
  for (uint64_t b = 0; b < blocks; ++b)
    compressed.push_back(formats::deflateBytes(bytes.subspan(b * kBlockBytes, b + 1 == blocks ? last : kBlockBytes), kLevel));
  std::string out;
  auto append = [&](uint64_t value) { out.append(reinterpret_cast<const char*>(&value), sizeof value); };
  append(blocks);
  append(uint64_t(kBlockBytes));
  append(last);
  for (const std::string& c : compressed) append(uint64_t(c.size()));
  for (const std::string& c : compressed) out += c;
  return out;
}

// The <AppendedData> section.
class Appended {
 public:
  // Appends `bytes` and returns the DataArray element that points at them.
  std::string array(const std::string& type, const std::string& nameAttribute, int components,
                    std::span<const uint8_t> bytes) {
    return packedArray(type, nameAttribute, components, packed(bytes));
  }
  // The same for an array packed already.
  std::string packedArray(const std::string& type, const std::string& nameAttribute, int components,
                          const std::string& packedBytes) {
    const uint64_t offset = m_bytes.size();
    m_bytes += packedBytes;
    std::string element = "<DataArray type=\"" + type + "\"" + nameAttribute;
    if (components != 1) element += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    return element + " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
  }
  const std::string& bytes() const { return m_bytes; }

 private:
  std::string m_bytes;
};

template <class T>
std::span<const uint8_t> asBytes(const std::vector<T>& values) {
  return {reinterpret_cast<const uint8_t*>(values.data()), values.size() * sizeof(T)};
}

// `text` as an XML attribute value.
std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string named(const std::string& name) { return " Name=\"" + escaped(name) + "\""; }

template <class Real>
std::vector<Real> coordinates(std::span<const Vec3> points, const std::filesystem::path& file) {
  std::vector<Real> out;
  out.reserve(3 * points.size());
  for (const Vec3& p : points) {
    if (!p.allFinite()) throw FileWriteError(file, "a point has a non-finite coordinate");
    out.insert(out.end(), {Real(p.x()), Real(p.y()), Real(p.z())});
  }
  return out;
}

std::string arrays(const std::vector<VtkDataArray>& data, size_t tuples, Appended& appended,
                   const std::filesystem::path& file) {
  std::string xml;
  for (const VtkDataArray& a : data) {
    if (a.components < 1 || a.values.size() != tuples * size_t(a.components))
      throw FileWriteError(file, "array \"" + a.name + "\" holds " + std::to_string(a.values.size()) +
                                     " values, expected " + std::to_string(tuples) + " x " +
                                     std::to_string(a.components));
    xml += appended.array("Float32", named(a.name), a.components, asBytes(a.values));
  }
  return xml;
}

// connectivity and offsets of cells of `size` points each.
template <size_t N>
std::string cells(std::span<const std::array<int32_t, N>> cells, size_t points, Appended& appended,
                  const std::filesystem::path& file) {
  std::vector<int32_t> connectivity, offsets;
  connectivity.reserve(N * cells.size());
  offsets.reserve(cells.size());
  for (const auto& cell : cells) {
    for (int32_t i : cell) {
      if (i < 0 || size_t(i) >= points)
        throw FileWriteError(file, "a cell names point " + std::to_string(i) + " of " + std::to_string(points));
      connectivity.push_back(i);
    }
    offsets.push_back(int32_t(connectivity.size()));
  }
  return appended.array("Int32", named("connectivity"), 1, asBytes(connectivity)) +
         appended.array("Int32", named("offsets"), 1, asBytes(offsets));
}

void writeFile(const std::string& type, const std::string& body, const Appended& appended,
               const OutputPath& file) {
  AtomicFile out(file);
  out.write("<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type +
            "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
            "compressor=\"vtkZLibDataCompressor\">\n<" +
            type + ">\n" + body + "</" + type + ">\n<AppendedData encoding=\"raw\">\n_");
  out.write(appended.bytes());
  out.write("\n</AppendedData>\n</VTKFile>\n");
  out.commit();
}

}  // namespace

void writePolyData(const VtkPolyData& data, const OutputPath& output) {
  const std::filesystem::path file = output.path();
  Appended appended;
  const size_t n = data.points.size();
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" +
                     std::to_string(data.vertices.size()) + "\" NumberOfLines=\"" + std::to_string(data.lines.size()) +
                     "\" NumberOfStrips=\"0\" NumberOfPolys=\"" + std::to_string(data.triangles.size()) + "\">\n";
  body += "<PointData>\n" + arrays(data.pointData, n, appended, file) + "</PointData>\n";
  body += "<Points>\n" + appended.array("Float32", "", 3, asBytes(coordinates<float>(data.points, file))) + "</Points>\n";
  std::vector<std::array<int32_t, 1>> vertices;
  for (int32_t i : data.vertices) vertices.push_back({i});
  body += "<Verts>\n" + cells<1>(vertices, n, appended, file) + "</Verts>\n";
  body += "<Lines>\n" + cells<2>(data.lines, n, appended, file) + "</Lines>\n";
  body += "<Polys>\n" + cells<3>(data.triangles, n, appended, file) + "</Polys>\n";
  body += "</Piece>\n";
  writeFile("PolyData", body, appended, output);
}

VtkTetCells::VtkTetCells(std::span<const std::array<int32_t, 4>> tets, std::span<const int32_t> labels, size_t points)
    : m_tets(tets.size()), m_points(points) {
  std::vector<int32_t> connectivity, offsets;
  connectivity.reserve(4 * tets.size());
  offsets.reserve(tets.size());
  for (const auto& tet : tets) {
    for (int32_t i : tet) {
      if (i < 0 || size_t(i) >= points)
        throw std::invalid_argument("a tetrahedron names point " + std::to_string(i) + " of " + std::to_string(points));
      connectivity.push_back(i);
    }
    offsets.push_back(int32_t(connectivity.size()));
  }
  if (!labels.empty() && labels.size() != tets.size())
    throw std::invalid_argument(std::to_string(labels.size()) + " labels for " + std::to_string(tets.size()) +
                                " tetrahedra");
  m_connectivity = packed(asBytes(connectivity));
  m_offsets = packed(asBytes(offsets));
  m_types = packed(asBytes(std::vector<uint8_t>(tets.size(), 10)));  // VTK_TETRA
  if (!labels.empty())
    m_labels = packed({reinterpret_cast<const uint8_t*>(labels.data()), labels.size() * sizeof(int32_t)});
}

void writeTetGrid(const VtkTetGrid& grid, const OutputPath& file) {
  try {
    const VtkTetCells cells(grid.tets, grid.labels, grid.points.size());
    writeTetGrid(grid.points, cells, grid.pointData, grid.cellData, file, grid.precision);
  } catch (const std::invalid_argument& e) {
    throw FileWriteError(file.path(), e.what());
  }
}

void writeTetGrid(std::span<const Vec3> points, const VtkTetCells& cells, const std::vector<VtkDataArray>& pointData,
                  const std::vector<VtkDataArray>& cellData, const OutputPath& output,
                  PointPrecision precision) {
  const std::filesystem::path file = output.path();
  if (points.size() != cells.m_points)
    throw FileWriteError(file, std::to_string(points.size()) + " points for cells of " +
                                   std::to_string(cells.m_points));
  Appended appended;
  std::string body = "<Piece NumberOfPoints=\"" + std::to_string(points.size()) + "\" NumberOfCells=\"" +
                     std::to_string(cells.m_tets) + "\">\n";
  body += "<PointData>\n" + arrays(pointData, points.size(), appended, file) + "</PointData>\n";
  std::string cellArrays = arrays(cellData, cells.m_tets, appended, file);
  if (!cells.m_labels.empty()) cellArrays += appended.packedArray("Int32", named("label"), 1, cells.m_labels);
  body += "<CellData>\n" + cellArrays + "</CellData>\n";
  body += "<Points>\n" +
          (precision == PointPrecision::kFloat64
               ? appended.array("Float64", "", 3, asBytes(coordinates<double>(points, file)))
               : appended.array("Float32", "", 3, asBytes(coordinates<float>(points, file)))) +
          "</Points>\n";
  body += "<Cells>\n" + appended.packedArray("Int32", named("connectivity"), 1, cells.m_connectivity) +
          appended.packedArray("Int32", named("offsets"), 1, cells.m_offsets) +
          appended.packedArray("UInt8", named("types"), 1, cells.m_types) + "</Cells>\n";
  body += "</Piece>\n";
  writeFile("UnstructuredGrid", body, appended, output);
}

void writeMultiBlock(const std::vector<std::pair<size_t, std::string>>& blocks, const OutputPath& file) {
  std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\">\n"
                    "<vtkMultiBlockDataSet>\n";
  for (const auto& [index, name] : blocks)
    xml += "<DataSet index=\"" + std::to_string(index) + "\" file=\"" + escaped(name) + "\"/>\n";
  xml += "</vtkMultiBlockDataSet>\n</VTKFile>\n";
  AtomicFile out(file);
  out.write(xml);
  out.commit();
}

void PvdCollection::add(double time, const std::string& file, int part) { m_entries.push_back({time, file, part}); }

void PvdCollection::write(const OutputPath& output) const {
  const std::filesystem::path file = output.path();
  std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const Entry& e : m_entries) {
    if (!std::isfinite(e.time)) throw FileWriteError(file, "a dataset of " + e.file + " has a non-finite time");
    xml += "<DataSet timestep=\"" + formatDouble(e.time) + "\" part=\"" + std::to_string(e.part) + "\" file=\"" +
           escaped(e.file) + "\"/>\n";
  }
  xml += "</Collection>\n</VTKFile>\n";
  AtomicFile out(output);
  out.write(xml);
  out.commit();
}

}  // namespace trephine::formats
