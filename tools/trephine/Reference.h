#pragma once
// `trephine components`: the reference of every component and field, from the
// registry with every available plugin loaded.
#include <iosfwd>
#include <string>

namespace trephine::cli {

enum class ReferenceFormat { Text, Json, Markdown, XmlSchema };

// Writes the reference; `only` restricts it to one component type. Returns false when `only` is unknown.
bool writeReference(std::ostream& out, ReferenceFormat format, const std::string& only, std::string& error);

}  // namespace trephine::cli
