#include "tools/trephine/XmlSchema.h"

#include <ostream>
#include <string>

#include "framework/core/Component.h"
#include "framework/core/Registry.h"

namespace trephine::cli {

namespace {

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// The schema only knows what XSD can say: enums, booleans, integers; other
// values (vectors, lists, links, paths, doubles with ranges) are checked by the loader.
std::string simpleTypeOf(const BaseField& field) {
  const std::string type = field.typeName();
  if (type == "bool") return "xs:boolean";
  if (type == "int") return "xs:integer";
  if (type == "double" || type == "rate") return "xs:double";
  return "xs:string";
}

void writeDocumentation(std::ostream& out, const std::string& indent, const std::string& text) {
  out << indent << "<xs:annotation><xs:documentation>" << escapeXml(text) << "</xs:documentation></xs:annotation>\n";
}

void writeAttribute(std::ostream& out, const BaseField& field) {
  out << "      <xs:attribute name=\"" << field.name() << "\"";
  const auto* enumField = dynamic_cast<const EnumField*>(&field);
  if (!enumField) out << " type=\"" << simpleTypeOf(field) << "\"";
  if (field.info().required) out << " use=\"required\"";
  out << ">\n";
  std::string help(field.info().help);
  if (!field.info().unit.empty()) help += " [" + std::string(field.info().unit) + "]";
  if (!field.defaultText().empty()) help += " (default " + field.defaultText() + ")";
  writeDocumentation(out, "        ", help);
  if (enumField) {
    out << "        <xs:simpleType><xs:restriction base=\"xs:string\">\n";
    for (const std::string& option : enumField->options())
      out << "          <xs:enumeration value=\"" << escapeXml(option) << "\"/>\n";
    out << "        </xs:restriction></xs:simpleType>\n";
  }
  out << "      </xs:attribute>\n";
}

}  // namespace

void writeXmlSchema(std::ostream& out, const Registry& registry) {
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<!-- Scene schema generated from the registry (trephine components, option xsd). The loader is the\n"
         "     authority: it also checks ranges, vectors, paths and links. -->\n"
         "<xs:schema xmlns:xs=\"http://www.w3.org/2001/XMLSchema\">\n";

  // Any component, a node, a plugin or an include may appear in a node, in any order.
  out << "  <xs:group name=\"member\">\n    <xs:choice>\n"
         "      <xs:element ref=\"Node\"/>\n      <xs:element ref=\"RequiredPlugin\"/>\n      <xs:element "
         "ref=\"Include\"/>\n";
  for (const ComponentEntry* entry : registry.entries()) out << "      <xs:element ref=\"" << entry->type << "\"/>\n";
  out << "    </xs:choice>\n  </xs:group>\n";

  out << "  <xs:element name=\"Node\">\n";
  writeDocumentation(out, "    ", "A group of components and nodes");
  out << "    <xs:complexType>\n      <xs:group ref=\"member\" minOccurs=\"0\" maxOccurs=\"unbounded\"/>\n"
         "      <xs:attribute name=\"name\" type=\"xs:string\"/>\n"
         "      <xs:attribute name=\"units\"><xs:simpleType><xs:restriction base=\"xs:string\">"
         "<xs:enumeration value=\"mm\"/></xs:restriction></xs:simpleType></xs:attribute>\n"
         "    </xs:complexType>\n  </xs:element>\n";
  out << "  <xs:element name=\"RequiredPlugin\">\n";
  writeDocumentation(out, "    ", "Loads the plugin trephine_<name>.so");
  out << "    <xs:complexType><xs:attribute name=\"name\" type=\"xs:string\" use=\"required\"/></xs:complexType>\n"
         "  </xs:element>\n";
  out << "  <xs:element name=\"Include\">\n";
  writeDocumentation(out, "    ", "Replaced by the root element of the file, relative to this one");
  out << "    <xs:complexType><xs:attribute name=\"file\" type=\"xs:string\" use=\"required\"/></xs:complexType>\n"
         "  </xs:element>\n";

  for (const ComponentEntry* entry : registry.entries()) {
    const auto prototype = entry->create();
    out << "  <xs:element name=\"" << entry->type << "\">\n";
    writeDocumentation(out, "    ", entry->summary + " (plugin " + entry->plugin + ")");
    out << "    <xs:complexType>\n";
    for (const BaseField* field : prototype->fields()) writeAttribute(out, *field);
    out << "    </xs:complexType>\n  </xs:element>\n";
  }
  out << "</xs:schema>\n";
}

}  // namespace trephine::cli
