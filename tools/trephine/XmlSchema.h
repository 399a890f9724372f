#pragma once
// An XML Schema (XSD 1.0) of scenes, generated from the registry, so that an
// editor can complete and check component tags, attribute names and enum values.
#include <iosfwd>

namespace trephine {
class Registry;
}

namespace trephine::cli {

void writeXmlSchema(std::ostream& out, const Registry& registry);

}  // namespace trephine::cli
