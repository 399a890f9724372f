#include "framework/formats/surface/SurfaceReader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include "framework/core/Strings.h"
#include "framework/formats/mesh/FileContent.h"
#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"
#include "framework/formats/vtk/VtkSurfaceReader.h"

namespace trephine::formats {

namespace {

// Appends the polygon `corners` as a fan of triangles; `where` names it in errors.
void addPolygon(TriangleMesh& s, const std::vector<int64_t>& corners, const TextCursor& cursor,
                const std::string& where) {
  if (corners.size() < 3) cursor.fail(where + " has " + std::to_string(corners.size()) + " corners; expected 3 or more");
  for (int64_t c : corners)
    if (c < 0 || c >= int64_t(s.vertices.size()))
      cursor.fail(where + " names vertex " + std::to_string(c) + " of " + std::to_string(s.vertices.size()));
  for (size_t k = 1; k + 1 < corners.size(); ++k)
    s.triangles.push_back({int32_t(corners[0]), int32_t(corners[k]), int32_t(corners[k + 1])});
}

Vec3 readPoint(TextCursor& cursor, const std::string& owner) {
  Vec3 p;
  for (int axis = 0; axis < 3; ++axis) {
    const std::string_view token = cursor.next();
    if (token.empty()) cursor.fail("the file ends inside " + owner);
    p[axis] = cursor.coordinate(token, axis, owner);
  }
  return p;
}

// ---- OFF ------------------------------------------------------------------------

TriangleMesh readOff(std::string_view text, const std::filesystem::path& file) {
  TextCursor cursor(text, file, '#');
  const std::string_view magic = cursor.next();
  if (!equalsIgnoreCase(magic, "OFF")) cursor.fail("expected the OFF header, found " + quoteForMessage(magic));
  const int64_t vertices = cursor.nextInteger("the vertex count");
  const int64_t faces = cursor.nextInteger("the face count");
  cursor.nextInteger("the edge count");
  cursor.checkCount(vertices, kMaxNodes, 6, "vertices");
  cursor.checkCount(faces, kMaxRecords, 4, "faces");
  TriangleMesh s;
  s.vertices.reserve(size_t(vertices));
  for (int64_t i = 0; i < vertices; ++i) {
    s.vertices.push_back(readPoint(cursor, "vertex " + std::to_string(i)));
    // Colours or other values may follow on the line.
    cursor.restOfLine();
  }
  std::vector<int64_t> corners;
  for (int64_t f = 0; f < faces; ++f) {
    const std::string where = "face " + std::to_string(f);
    const int64_t count = cursor.nextInteger("the corner count of " + where);
    cursor.checkCount(count, 1 << 20, 2, "corners of " + where);
    corners.clear();
    for (int64_t k = 0; k < count; ++k) corners.push_back(cursor.nextInteger("a corner of " + where));
    addPolygon(s, corners, cursor, where);
    cursor.restOfLine();
  }
  return s;
}

// ---- OBJ ------------------------------------------------------------------------

TriangleMesh readObj(std::string_view text, const std::filesystem::path& file) {
  TextCursor cursor(text, file, '#');
  TriangleMesh s;
  std::vector<std::string_view> tokens;
  std::vector<int64_t> corners;
  while (cursor.nextLine(tokens)) {
    if (tokens[0] == "v") {
      if (tokens.size() < 4) cursor.fail("a vertex needs x y z");
      Vec3 p;
      for (int axis = 0; axis < 3; ++axis)
        p[axis] = cursor.coordinate(tokens[size_t(axis) + 1], axis, "vertex " + std::to_string(s.vertices.size() + 1));
      if (int64_t(s.vertices.size()) >= kMaxNodes) cursor.fail("more than " + std::to_string(kMaxNodes) + " vertices");
      s.vertices.push_back(p);
    } else if (tokens[0] == "f") {
      corners.clear();
      for (size_t k = 1; k < tokens.size(); ++k) {
        // "7", "7/1", "7//3", "7/1/3": the vertex is the first number;
        // negative numbers count back from the last vertex read.
        const std::string_view token = tokens[k].substr(0, tokens[k].find('/'));
        const auto index = parseInteger(token);
        if (!index || *index == 0) cursor.fail("expected a vertex number in the face, found " + quoteForMessage(tokens[k]));
        const int64_t read = int64_t(s.vertices.size());
        if (*index > read || *index < -read)
          cursor.fail("the face names vertex " + std::to_string(*index) + " but " + std::to_string(read) +
                      " vertices are read so far");
        corners.push_back(*index > 0 ? *index - 1 : read + *index);
      }
      addPolygon(s, corners, cursor, "the face");
    }
    // Normals, texture coordinates, groups, materials: not needed.
  }
  return s;
}

// ---- STL ------------------------------------------------------------------------

// Corners that are the same point become one vertex (STL repeats them per triangle).
class VertexWelder {
 public:
  explicit VertexWelder(TriangleMesh& s) : m_s(s) {}
  int32_t add(const Vec3& p) {
    Key key;
    std::memcpy(key.bits, p.data(), sizeof key.bits);
    const auto [it, inserted] = m_index.try_emplace(key, int32_t(m_s.vertices.size()));
    if (inserted) m_s.vertices.push_back(p);
    return it->second;
  }

 private:
  struct Key {
    uint64_t bits[3];
    bool operator==(const Key& o) const { return std::equal(bits, bits + 3, o.bits); }
  };
  struct Hash {
    size_t operator()(const Key& k) const { return size_t(k.bits[0] * 73856093u ^ k.bits[1] * 19349663u ^ k.bits[2] * 83492791u); }
  };
  TriangleMesh& m_s;
  std::unordered_map<Key, int32_t, Hash> m_index;
};

TriangleMesh readAsciiStl(std::string_view text, const std::filesystem::path& file) {
  TextCursor cursor(text, file);
  TriangleMesh s;
  VertexWelder weld(s);
  cursor.next();  // solid
  cursor.restOfLine();  // its name
  std::array<int32_t, 3> triangle{};
  int corner = 0;
  while (!cursor.atEnd()) {
    const std::string_view word = cursor.next();
    if (equalsIgnoreCase(word, "vertex")) {
      if (corner == 3) cursor.fail("a facet with more than three vertices");
      triangle[size_t(corner++)] = weld.add(readPoint(cursor, "a vertex"));
    } else if (equalsIgnoreCase(word, "endloop")) {
      if (corner != 3) cursor.fail("a facet with " + std::to_string(corner) + " vertices; expected 3");
      s.triangles.push_back(triangle);
      corner = 0;
    } else if (equalsIgnoreCase(word, "normal")) {
      readPoint(cursor, "a facet normal");
    }
    // facet, outer, loop, endfacet, endsolid and the solid's name: structure only.
  }
  return s;
}

float littleEndianFloat(const char* p) {
  uint32_t bits;
  std::memcpy(&bits, p, 4);
  if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
  return std::bit_cast<float>(bits);
}

TriangleMesh readBinaryStl(std::string_view bytes, const std::filesystem::path& file) {
  if (bytes.size() < 84) throw TetMeshReadError(file, "a binary STL file has an 84-byte header; this one has " + std::to_string(bytes.size()) + " bytes");
  uint32_t count;
  std::memcpy(&count, bytes.data() + 80, 4);
  if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
  if (bytes.size() != 84 + 50 * uint64_t(count))
    throw TetMeshReadError(file, "the header counts " + std::to_string(count) + " triangles (" +
                                     std::to_string(84 + 50 * uint64_t(count)) + " bytes) but the file has " +
                                     std::to_string(bytes.size()) + " bytes");
  TriangleMesh s;
  VertexWelder weld(s);
  s.triangles.reserve(count);
  for (uint32_t t = 0; t < count; ++t) {
    const char* record = bytes.data() + 84 + 50 * size_t(t);
    std::array<int32_t, 3> triangle;
    for (int c = 0; c < 3; ++c) {
      Vec3 p;
      for (int axis = 0; axis < 3; ++axis) p[axis] = littleEndianFloat(record + 12 + 12 * c + 4 * axis);
      if (!p.allFinite())
        throw TetMeshReadError(file, "triangle " + std::to_string(t) + " (byte " + std::to_string(84 + 50 * size_t(t)) +
                                         ") has a coordinate that is not a finite number");
      triangle[size_t(c)] = weld.add(p);
    }
    s.triangles.push_back(triangle);
  }
  return s;
}

// ---- PLY ------------------------------------------------------------------------

enum class PlyFormat { kAscii, kLittle, kBig };

struct PlyProperty {
  std::string name;
  int size = 0;       // bytes of a scalar, or of a list's items
  bool isReal = false;
  bool isSigned = false;
  bool isList = false;
  int countSize = 0;  // bytes of a list's count
};

struct PlyElement {
  std::string name;
  int64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool plyType(std::string_view type, int& size, bool& isReal, bool& isSigned) {
  struct Type {
    const char* a;
    const char* b;
    int size;
    bool real, sign;
  };
  static const Type kTypes[] = {{"char", "int8", 1, false, true},      {"uchar", "uint8", 1, false, false},
                                {"short", "int16", 2, false, true},    {"ushort", "uint16", 2, false, false},
                                {"int", "int32", 4, false, true},      {"uint", "uint32", 4, false, false},
                                {"float", "float32", 4, true, true},   {"double", "float64", 8, true, true}};
  for (const Type& t : kTypes)
    if (type == t.a || type == t.b) {
      size = t.size;
      isReal = t.real;
      isSigned = t.sign;
      return true;
    }
  return false;
}

class PlyBinary {
 public:
  PlyBinary(std::string_view bytes, size_t start, bool big, const std::filesystem::path& file)
      : m_bytes(bytes), m_pos(start), m_big(big), m_file(file) {}
  double read(int size, bool isReal, bool isSigned) {
    if (m_pos + size_t(size) > m_bytes.size())
      throw TetMeshReadError(m_file, "the binary data ends at byte " + std::to_string(m_bytes.size()) +
                                         " before the header's elements are read (truncated?)");
    unsigned char b[8];
    std::memcpy(b, m_bytes.data() + m_pos, size_t(size));
    m_pos += size_t(size);
    if (m_big != (std::endian::native == std::endian::big)) std::reverse(b, b + size);
    if (isReal) {
      if (size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      }
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
    // Integers, now in the host's byte order.
    switch (size) {
      case 1:
        return isSigned ? double(int8_t(b[0])) : double(b[0]);
      case 2: {
        uint16_t u;
        std::memcpy(&u, b, 2);
        return isSigned ? double(int16_t(u)) : double(u);
      }
      default: {
        uint32_t u;
        std::memcpy(&u, b, 4);
        return isSigned ? double(int32_t(u)) : double(u);
      }
    }
  }
  size_t position() const { return m_pos; }

 private:
  std::string_view m_bytes;
  size_t m_pos;
  bool m_big;
  const std::filesystem::path& m_file;
};

TriangleMesh readPly(std::string_view text, const std::filesystem::path& file) {
  TextCursor cursor(text, file);
  std::vector<std::string_view> tokens;
  cursor.nextLine(tokens);  // "ply"
  PlyFormat format = PlyFormat::kAscii;
  bool formatSeen = false;
  std::vector<PlyElement> elements;
  for (;;) {
    if (!cursor.nextLine(tokens)) cursor.fail("the header has no end_header line");
    if (tokens[0] == "end_header") break;
    if (tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "format") {
      if (tokens.size() < 2) cursor.fail("format needs a name");
      if (tokens[1] == "ascii") format = PlyFormat::kAscii;
      else if (tokens[1] == "binary_little_endian") format = PlyFormat::kLittle;
      else if (tokens[1] == "binary_big_endian") format = PlyFormat::kBig;
      else cursor.fail("unknown format " + quoteForMessage(tokens[1]) + "; expected ascii, binary_little_endian or binary_big_endian");
      formatSeen = true;
    } else if (tokens[0] == "element") {
      if (tokens.size() < 3) cursor.fail("an element needs a name and a count");
      const auto count = parseInteger(tokens[2]);
      if (!count || *count < 0 || *count > kMaxRecords) cursor.fail("element " + quoteForMessage(tokens[1]) + " has count " + quoteForMessage(tokens[2]));
      elements.push_back({std::string(tokens[1]), *count, {}});
    } else if (tokens[0] == "property") {
      if (elements.empty()) cursor.fail("a property before any element");
      PlyProperty p;
      size_t name = 2;
      if (tokens.size() >= 2 && tokens[1] == "list") {
        if (tokens.size() < 5) cursor.fail("a list property needs a count type, an item type and a name");
        bool real = false, sign = false;
        if (!plyType(tokens[2], p.countSize, real, sign) || real) cursor.fail("a list's count type must be an integer type, not " + quoteForMessage(tokens[2]));
        if (!plyType(tokens[3], p.size, p.isReal, p.isSigned)) cursor.fail("unknown type " + quoteForMessage(tokens[3]));
        p.isList = true;
        name = 4;
      } else if (tokens.size() < 3 || !plyType(tokens[1], p.size, p.isReal, p.isSigned)) {
        cursor.fail("unknown property type " + quoteForMessage(tokens.size() > 1 ? tokens[1] : std::string_view()));
      }
      p.name = std::string(tokens[name]);
      elements.back().properties.push_back(p);
    } else {
      cursor.fail("unexpected header line starting " + quoteForMessage(tokens[0]));
    }
  }
  if (!formatSeen) cursor.fail("the header has no format line");
  TriangleMesh s;
  const size_t dataStart = text.size() - cursor.bytesLeft();
  PlyBinary binary(text, dataStart, format == PlyFormat::kBig, file);
  std::vector<double> values;
  std::vector<int64_t> corners;
  for (const PlyElement& element : elements) {
    const bool isVertex = element.name == "vertex", isFace = element.name == "face";
    int axes[3] = {-1, -1, -1};
    int list = -1;
    for (size_t k = 0; k < element.properties.size(); ++k) {
      const PlyProperty& p = element.properties[k];
      if (isVertex && !p.isList && (p.name == "x" || p.name == "y" || p.name == "z")) axes[p.name[0] - 'x'] = int(k);
      if (isFace && p.isList && (p.name == "vertex_indices" || p.name == "vertex_index")) list = int(k);
    }
    if (isVertex && (axes[0] < 0 || axes[1] < 0 || axes[2] < 0)) cursor.fail("the vertex element lacks x, y or z");
    if (isFace && list < 0) cursor.fail("the face element lacks a vertex_indices list");
    for (int64_t r = 0; r < element.count; ++r) {
      const std::string owner = element.name + " " + std::to_string(r);
      values.clear();
      corners.clear();
      for (size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& p = element.properties[k];
        const auto one = [&](int size, bool real, bool sign) {
          if (format == PlyFormat::kAscii) {
            const std::string_view token = cursor.next();
            if (token.empty()) cursor.fail("the file ends inside " + owner);
            const auto v = parseReal(token);
            if (!v) cursor.fail("expected a number in " + owner + ", found " + quoteForMessage(token));
            return *v;
          }
          return binary.read(size, real, sign);
        };
        if (!p.isList) {
          values.push_back(one(p.size, p.isReal, p.isSigned));
          continue;
        }
        const double n = one(p.countSize, false, false);
        if (!(n >= 0 && n <= (1 << 20))) cursor.fail(owner + " has a list of " + std::to_string(n) + " items");
        for (int64_t i = 0; i < int64_t(n); ++i) {
          const double item = one(p.size, p.isReal, p.isSigned);
          if (int(k) != list) continue;
          // A whole number within int32 before it becomes one (a huge or
          // fractional value is no index; its conversion would be undefined).
          if (!(std::abs(item) <= 2147483647.0) || item != std::floor(item))
            cursor.fail(owner + " lists the vertex index " + formatDouble(item) + " (expected a whole number)");
          corners.push_back(int64_t(item));
        }
        values.push_back(n);
      }
      if (isVertex) {
        const Vec3 p(values[size_t(axes[0])], values[size_t(axes[1])], values[size_t(axes[2])]);
        if (!p.allFinite()) cursor.fail(owner + " has a coordinate that is not a finite number");
        s.vertices.push_back(p);
      } else if (isFace) {
        addPolygon(s, corners, cursor, owner);
      }
    }
  }
  return s;
}

}  // namespace

TriangleMesh readSurface(const std::filesystem::path& file) {
  const std::string content = readFileContent(file);
  const std::string_view text(content);
  std::string extension = file.extension().string();
  if (extension == ".gz") extension = file.stem().extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  TriangleMesh s;
  if (startsWithIgnoreCase(text, "OFF")) {
    s = readOff(text, file);
  } else if (text.starts_with("ply")) {
    s = readPly(text, file);
  } else if (startsWithIgnoreCase(text, "solid") && text.find("facet") != std::string_view::npos &&
             text.find("vertex") < 1000) {
    s = readAsciiStl(text, file);
  } else if (extension == ".stl") {
    s = readBinaryStl(text, file);
  } else if (extension == ".obj") {
    s = readObj(text, file);
  } else if (text.substr(0, 512).find("<VTKFile") != std::string_view::npos) {
    s = readVtkPolyData(file, text);
  } else {
    throw TetMeshReadError(file, "not a surface this program reads: expected OFF, PLY, ASCII STL or VTK XML poly data "
                                 "content, or a .obj or binary .stl file");
  }
  if (s.triangles.empty()) throw TetMeshReadError(file, "the surface has no triangle");
  return s;
}

}  // namespace trephine::formats
