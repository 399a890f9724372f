#include "framework/formats/vtk/VtkSurfaceReader.h"

#include <tinyxml2.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "framework/formats/encoding/Inflate.h"

namespace trephine::vtk {

namespace {

struct AppendedFile {
  std::string path, bytes;
  size_t binaryStart = std::string::npos;  // after the '_' of AppendedData
  bool compressed = false, header64 = false;

  [[noreturn]] void fail(const std::string& what) const { throw VtkReadError(path + ": " + what); }

  uint64_t word(size_t at) const {
    const size_t size = header64 ? 8 : 4;
    if (at + size > bytes.size()) fail("an array header runs past the end of the file");
    uint64_t v = 0;
    std::memcpy(&v, bytes.data() + at, size);  // little-endian, checked at open
    return v;
  }

  // The bytes of the appended array at `offset`.
  std::vector<uint8_t> array(uint64_t offset, const std::string& name) const {
    const size_t w = header64 ? 8 : 4;
    if (offset > bytes.size() - binaryStart) fail(name + ": offset " + std::to_string(offset) + " past the end");
    const size_t start = binaryStart + offset;
    std::vector<uint8_t> out;
    if (!compressed) {
      const uint64_t size = word(start);
      if (size > bytes.size() - start - w) fail(name + ": its data run past the end of the file");
      out.assign(bytes.begin() + start + w, bytes.begin() + start + w + size);
      return out;
    }
    const uint64_t blocks = word(start), blockSize = word(start + w), last = word(start + 2 * w);
    if (blocks > (bytes.size() - start) / w) fail(name + ": more blocks than the file holds");
    if (blocks && (blockSize == 0 || last > blockSize || blockSize > (uint64_t(1) << 30)))
      fail(name + ": block sizes " + std::to_string(blockSize) + " and " + std::to_string(last) + " are not valid");
    const uint64_t total = blocks ? (blocks - 1) * blockSize + (last ? last : blockSize) : 0;
    size_t at = start + (3 + blocks) * w;
    uint64_t compressedTotal = 0;
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t size = word(start + (3 + b) * w);
      if (size > bytes.size()) fail(name + ": block " + std::to_string(b) + " is larger than the file");
      compressedTotal += size;
    }
    if (compressedTotal > bytes.size() - std::min(at, bytes.size()) || total > formats::maxInflatedSize(compressedTotal))
      fail(name + ": its blocks run past the end of the file");
    out.resize(total);
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t size = word(start + (3 + b) * w);
      const size_t produced = b + 1 == blocks ? total - b * blockSize : blockSize;
      if (auto problem = formats::inflateExactly({reinterpret_cast<const uint8_t*>(bytes.data()) + at, size},
                                        {out.data() + b * blockSize, produced}))
        fail(name + ": block " + std::to_string(b) + ": " + *problem);
      at += size;
    }
    return out;
  }
};

// The values of a DataArray element as doubles (points) or int64 (indices).
template <class Out>
std::vector<Out> values(const AppendedFile& file, const tinyxml2::XMLElement* e, const std::string& name) {
  if (!e) file.fail("no " + name + " array");
  const char* format = e->Attribute("format");
  if (!format || std::string(format) != "appended") file.fail(name + ": only appended arrays are read");
  uint64_t offset = 0;
  if (e->QueryUnsigned64Attribute("offset", &offset) != tinyxml2::XML_SUCCESS) file.fail(name + ": no offset");
  const std::string type = e->Attribute("type") ? e->Attribute("type") : "";
  const std::vector<uint8_t> bytes = file.array(offset, name);
  std::vector<Out> out;
  auto convert = [&]<class T>(T) {
    if (bytes.size() % sizeof(T)) file.fail(name + ": " + std::to_string(bytes.size()) + " bytes is not whole " + type + "s");
    out.resize(bytes.size() / sizeof(T));
    for (size_t i = 0; i < out.size(); ++i) {
      T v;
      std::memcpy(&v, bytes.data() + i * sizeof(T), sizeof(T));
      out[i] = static_cast<Out>(v);
    }
  };
  if (type == "Float32") convert(float{});
  else if (type == "Float64") convert(double{});
  else if (type == "Int32") convert(int32_t{});
  else if (type == "Int64") convert(int64_t{});
  else if (type == "UInt32") convert(uint32_t{});
  else if (type == "UInt64") convert(uint64_t{});
  else file.fail(name + ": type " + type + " (expected Float32, Float64, Int32, Int64, UInt32 or UInt64)");
  return out;
}

const tinyxml2::XMLElement* arrayNamed(const tinyxml2::XMLElement* section, const char* name) {
  if (!section) return nullptr;
  for (const auto* e = section->FirstChildElement("DataArray"); e; e = e->NextSiblingElement("DataArray")) {
    const char* n = e->Attribute("Name");
    if (!name || (n && std::string(n) == name)) return e;
  }
  return nullptr;
}

}  // namespace

TriangleMesh readTriangleSurface(const std::filesystem::path& path) {
  AppendedFile file;
  file.path = path.string();
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) file.fail("cannot be read");
    std::ostringstream all;
    all << in.rdbuf();
    file.bytes = all.str();
  }
  const size_t appended = file.bytes.find("<AppendedData");
  std::string header = file.bytes.substr(0, appended);
  if (appended != std::string::npos) {
    header += "</VTKFile>";
    const size_t underscore = file.bytes.find('_', appended);
    if (underscore == std::string::npos) file.fail("AppendedData without its '_' marker");
    file.binaryStart = underscore + 1;
  }
  tinyxml2::XMLDocument document;
  if (document.Parse(header.data(), header.size()) != tinyxml2::XML_SUCCESS)
    file.fail("line " + std::to_string(document.ErrorLineNum()) + ": not VTK XML (" + document.ErrorStr() + ")");
  const auto* root = document.RootElement();
  if (!root || std::string(root->Name()) != "VTKFile" || !root->Attribute("type", "PolyData"))
    file.fail("expected a VTKFile of type PolyData");
  if (root->Attribute("byte_order", "BigEndian")) file.fail("big-endian files are not read");
  file.compressed = root->Attribute("compressor", "vtkZLibDataCompressor");
  if (root->Attribute("compressor") && !file.compressed)
    file.fail(std::string("compressor ") + root->Attribute("compressor") + " (only vtkZLibDataCompressor is read)");
  file.header64 = root->Attribute("header_type", "UInt64");
  const auto* polyData = root->FirstChildElement("PolyData");
  const auto* piece = polyData ? polyData->FirstChildElement("Piece") : nullptr;
  if (!piece) file.fail("no PolyData Piece");
  TriangleMesh surface;
  int64_t pointCount = 0, polyCount = 0;
  piece->QueryInt64Attribute("NumberOfPoints", &pointCount);
  piece->QueryInt64Attribute("NumberOfPolys", &polyCount);
  if (pointCount == 0) return surface;
  if (file.binaryStart == std::string::npos) file.fail("no AppendedData");
  const std::vector<double> xyz = values<double>(file, arrayNamed(piece->FirstChildElement("Points"), nullptr), "Points");
  if (xyz.size() != size_t(pointCount) * 3)
    file.fail("Points holds " + std::to_string(xyz.size()) + " values for " + std::to_string(pointCount) + " points");
  surface.vertices.resize(size_t(pointCount));
  for (size_t i = 0; i < surface.vertices.size(); ++i) surface.vertices[i] = Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  if (polyCount == 0) return surface;
  const auto* polys = piece->FirstChildElement("Polys");
  const std::vector<int64_t> connectivity = values<int64_t>(file, arrayNamed(polys, "connectivity"), "Polys/connectivity");
  const std::vector<int64_t> offsets = values<int64_t>(file, arrayNamed(polys, "offsets"), "Polys/offsets");
  if (offsets.size() != size_t(polyCount)) file.fail("Polys/offsets holds " + std::to_string(offsets.size()) + " values for " + std::to_string(polyCount) + " polygons");
  int64_t start = 0;
  for (const int64_t end : offsets) {
    if (end < start || end > int64_t(connectivity.size())) file.fail("Polys/offsets are not increasing within the connectivity");
    if (end - start == 3) {
      std::array<int32_t, 3> t;
      for (int k = 0; k < 3; ++k) {
        const int64_t v = connectivity[size_t(start + k)];
        if (v < 0 || v >= pointCount) file.fail("Polys/connectivity: point " + std::to_string(v) + " of " + std::to_string(pointCount));
        t[k] = int32_t(v);
      }
      surface.triangles.push_back(t);
    }
    start = end;
  }
  return surface;
}

}  // namespace trephine::vtk
