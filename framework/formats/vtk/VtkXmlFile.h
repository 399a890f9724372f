#pragma once
// A VTK XML file opened for reading, whatever its dataset (.vtu grids, .vtp
// poly data): its XML parsed with the bytes of <AppendedData> cut out (line
// numbers stay those of the file), its encoding read from <VTKFile> (byte
// order, header type, zlib compressor, appended raw or base64), and its
// DataArrays decoded by VtkXmlArrays. Every problem is a FileReadError that
// names the file and the line. tinyxml2's types are only named here and
// used by the readers' .cpp files.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "framework/formats/vtk/VtkXmlArrays.h"

namespace tinyxml2 {
class XMLDocument;
class XMLElement;
}  // namespace tinyxml2

namespace trephine::formats {

class VtkXmlFile {
 public:
  using Element = tinyxml2::XMLElement;

  // `type`: the dataset the reader expects ("UnstructuredGrid", "PolyData"),
  // checked against <VTKFile type="...">. `content` must outlive this.
  VtkXmlFile(const std::filesystem::path& file, std::string_view content, std::string_view type);
  ~VtkXmlFile();

  // The <type> element under <VTKFile>.
  const Element& dataSet() const { return *m_dataSet; }

  [[noreturn]] void fail(const Element* element, const std::string& problem) const;
  // A whole-number attribute of a <Piece> in [0, maxCount].
  int64_t count(const Element& piece, const char* name, int64_t maxCount) const;
  // NumberOfComponents (1 when absent).
  int64_t components(const Element& array) const;
  // The DataArray named `name` among `parent`'s children, or an error naming both.
  const Element& namedArray(const Element& parent, std::string_view name) const;
  // Exactly `count` values of the array.
  std::vector<double> reals(const Element& array, int64_t count) const;
  std::vector<int64_t> integers(const Element& array, int64_t count) const;

 private:
  VtkXmlArray describe(const Element& array) const;
  size_t lineAt(size_t position) const;
  std::string_view withoutAppendedData(std::string& cut);
  void readEncoding(const Element& root);
  void readAppendedEncoding(const Element& root);

  const std::filesystem::path& m_file;
  std::string_view m_content;
  std::string m_cut;  // the XML without the appended bytes, when there are some
  VtkXmlEncoding m_encoding;
  std::unique_ptr<tinyxml2::XMLDocument> m_document;
  const Element* m_dataSet = nullptr;
};

// The value of an attribute, empty when absent.
std::string_view vtkXmlAttribute(const VtkXmlFile::Element& element, const char* name);

}  // namespace trephine::formats
