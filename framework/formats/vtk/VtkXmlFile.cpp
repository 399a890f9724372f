#include "framework/formats/vtk/VtkXmlFile.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <optional>

#include "framework/formats/FileReadError.h"
#include "framework/formats/encoding/TextTokens.h"

namespace trephine::formats {

namespace {

// The first `needle` in `text` that is not inside an XML comment.
size_t findOutsideComments(std::string_view text, std::string_view needle) {
  size_t from = 0;
  for (;;) {
    const size_t hit = text.find(needle, from);
    const size_t comment = text.find("<!--", from);
    if (hit == std::string_view::npos || comment == std::string_view::npos || hit < comment) return hit;
    const size_t commentEnd = text.find("-->", comment + 4);
    if (commentEnd == std::string_view::npos) return std::string_view::npos;
    from = commentEnd + 3;
  }
}

}  // namespace

std::string_view vtkXmlAttribute(const VtkXmlFile::Element& element, const char* name) {
  const char* value = element.Attribute(name);
  return value ? std::string_view(value) : std::string_view();
}

VtkXmlFile::VtkXmlFile(const std::filesystem::path& file, std::string_view content, std::string_view type)
    : m_file(file), m_content(content), m_document(std::make_unique<tinyxml2::XMLDocument>()) {
  // <AppendedData> holds raw bytes or base64 text, not XML: it is cut out
  // and the XML before and after it parsed.
  const std::string_view xml = withoutAppendedData(m_cut);
  if (m_document->Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw FileReadError(m_file, size_t(std::max(m_document->ErrorLineNum(), 1)),
                        std::string("not well-formed XML (") + m_document->ErrorName() + ")");
  const Element* root = m_document->RootElement();
  const std::string expected = "<VTKFile type=\"" + std::string(type) + "\">";
  if (!root || std::string_view(root->Name()) != "VTKFile")
    fail(root, "the XML root is <" + std::string(root ? root->Name() : "") + ">, expected " + expected);
  const std::string_view fileType = vtkXmlAttribute(*root, "type");
  if (fileType != type)
    fail(root, "VTKFile type " + quoteForMessage(fileType) + ", expected \"" + std::string(type) + "\"" +
                   (fileType == "P" + std::string(type) ? " (a parallel index only lists the pieces)" : ""));
  readEncoding(*root);
  if (m_encoding.hasAppended) readAppendedEncoding(*root);
  m_dataSet = root->FirstChildElement(std::string(type).c_str());
  if (!m_dataSet) fail(root, "VTKFile has no <" + std::string(type) + "> element");
}

VtkXmlFile::~VtkXmlFile() = default;

void VtkXmlFile::fail(const Element* element, const std::string& problem) const {
  throw FileReadError(m_file, element ? size_t(element->GetLineNum()) : 0, problem);
}

void VtkXmlFile::readEncoding(const Element& root) {
  const std::string_view byteOrder = vtkXmlAttribute(root, "byte_order");
  if (byteOrder == "BigEndian")
    m_encoding.bigEndian = true;
  else if (!byteOrder.empty() && byteOrder != "LittleEndian")
    fail(&root, "byte_order " + quoteForMessage(byteOrder) + ", expected \"LittleEndian\" or \"BigEndian\"");
  const std::string_view headerType = vtkXmlAttribute(root, "header_type");
  if (headerType == "UInt64")
    m_encoding.header64 = true;
  else if (!headerType.empty() && headerType != "UInt32")
    fail(&root, "header_type " + quoteForMessage(headerType) + ", expected \"UInt32\" or \"UInt64\"");
  const std::string_view compressor = vtkXmlAttribute(root, "compressor");
  if (compressor == "vtkZLibDataCompressor")
    m_encoding.zlib = true;
  else if (!compressor.empty())
    fail(&root, "compressor " + quoteForMessage(compressor) +
                    " is not supported, expected none or \"vtkZLibDataCompressor\"");
}

size_t VtkXmlFile::lineAt(size_t position) const {
  return size_t(std::count(m_content.begin(), m_content.begin() + std::ptrdiff_t(position), '\n')) + 1;
}

std::string_view VtkXmlFile::withoutAppendedData(std::string& cut) {
  const size_t tag = findOutsideComments(m_content, "<AppendedData");
  if (tag == std::string_view::npos) return m_content;
  const size_t tagEnd = m_content.find('>', tag);
  if (tagEnd == std::string_view::npos)
    throw FileReadError(m_file, lineAt(tag), "the <AppendedData> tag is not closed (truncated?)");
  size_t marker = tagEnd + 1;
  while (marker < m_content.size() && std::isspace(static_cast<unsigned char>(m_content[marker]))) ++marker;
  if (marker >= m_content.size() || m_content[marker] != '_')
    throw FileReadError(m_file, lineAt(tag),
                        "<AppendedData> has no '_' before its data (expected \"<AppendedData "
                        "encoding=...>\" then \"_\" and the data)");
  const size_t close = m_content.rfind("</AppendedData>");
  if (close == std::string_view::npos || close < marker)
    throw FileReadError(m_file, lineAt(tag), "<AppendedData> has no closing </AppendedData> (truncated?)");
  m_encoding.hasAppended = true;
  m_encoding.appended = m_content.substr(marker + 1, close - marker - 1);
  cut = std::string(m_content.substr(0, marker + 1)) + std::string(m_content.substr(close));
  return cut;
}

void VtkXmlFile::readAppendedEncoding(const Element& root) {
  const Element* appended = root.FirstChildElement("AppendedData");
  if (!appended) fail(&root, "<AppendedData> is not inside <VTKFile>");
  const std::string_view encoding = vtkXmlAttribute(*appended, "encoding");
  if (encoding == "base64")
    m_encoding.appendedBase64 = true;
  else if (encoding != "raw")
    fail(appended, "<AppendedData> encoding " + (encoding.data() ? quoteForMessage(encoding) : "missing") +
                       ", expected \"raw\" or \"base64\"");
}

int64_t VtkXmlFile::count(const Element& piece, const char* name, int64_t maxCount) const {
  const std::string_view text = vtkXmlAttribute(piece, name);
  const std::optional<int64_t> value = parseInteger(text);
  if (!value || *value < 0 || *value > maxCount)
    fail(&piece, std::string("<Piece> ") + name + " is " + (text.data() ? quoteForMessage(text) : "missing") +
                     ", expected a whole number from 0 to " + std::to_string(maxCount));
  return *value;
}

VtkXmlArray VtkXmlFile::describe(const Element& array) const {
  VtkXmlArray described;
  described.name = vtkXmlAttribute(array, "Name");
  // Unnamed arrays (the points) are named by their parent element in messages.
  if (described.name.empty() && array.Parent() && array.Parent()->ToElement())
    described.name = array.Parent()->ToElement()->Name();
  described.type = vtkXmlAttribute(array, "type");
  described.format = vtkXmlAttribute(array, "format");
  const char* text = array.GetText();
  described.text = text ? std::string_view(text) : std::string_view();
  described.line = size_t(array.GetLineNum());
  if (described.format == "appended") {
    const std::string_view offset = vtkXmlAttribute(array, "offset");
    const std::optional<int64_t> value = parseInteger(offset);
    if (!value || *value < 0)
      fail(&array, "DataArray \"" + std::string(described.name) + "\": offset " +
                       (offset.data() ? quoteForMessage(offset) : "missing") +
                       ", expected the position of its data in <AppendedData> (a whole number from 0)");
    described.offset = uint64_t(*value);
  }
  return described;
}

int64_t VtkXmlFile::components(const Element& array) const {
  const std::string_view text = vtkXmlAttribute(array, "NumberOfComponents");
  if (text.empty()) return 1;
  const std::optional<int64_t> value = parseInteger(text);
  if (!value || *value < 1) fail(&array, "NumberOfComponents " + quoteForMessage(text) + ", expected 1 or more");
  return *value;
}

const VtkXmlFile::Element& VtkXmlFile::namedArray(const Element& parent, std::string_view name) const {
  for (const Element* array = parent.FirstChildElement("DataArray"); array;
       array = array->NextSiblingElement("DataArray"))
    if (vtkXmlAttribute(*array, "Name") == name) return *array;
  fail(&parent, "<" + std::string(parent.Name()) + "> has no DataArray named \"" + std::string(name) + "\"");
}

std::vector<double> VtkXmlFile::reals(const Element& array, int64_t count) const {
  return readVtkXmlReals(describe(array), count, m_encoding, m_file);
}

std::vector<int64_t> VtkXmlFile::integers(const Element& array, int64_t count) const {
  return readVtkXmlIntegers(describe(array), count, m_encoding, m_file);
}

}  // namespace trephine::formats
