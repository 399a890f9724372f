#include "tools/trephine/Reference.h"

#include <ostream>

#include "framework/core/Component.h"
#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "framework/core/Strings.h"
#include "framework/runtime/JsonWriter.h"
#include "framework/runtime/Simulation.h"
#include "tools/trephine/XmlSchema.h"

namespace trephine::cli {

namespace {

std::string markdownCell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

}  // namespace

bool writeReference(std::ostream& out, ReferenceFormat format, const std::string& only, std::string& error) {
  Registry registry;
  registerCoreComponents(registry);
  PluginLoader plugins;
  for (const std::string& name : plugins.available()) {
    if (auto e = plugins.load(name, registry)) error += (error.empty() ? "" : "\n") + *e;
  }
  std::vector<const ComponentEntry*> entries;
  for (const ComponentEntry* entry : registry.entries())
    if (only.empty() || entry->type == only) entries.push_back(entry);
  if (!only.empty() && entries.empty()) {
    error = "unknown component '" + only + "'" + didYouMean(only, registry.typeNames());
    return false;
  }

  if (format == ReferenceFormat::XmlSchema) {
    writeXmlSchema(out, registry);
    return true;
  }
  if (format == ReferenceFormat::Json) {
    JsonWriter json(out);
    json.beginObject();
    for (const ComponentEntry* entry : entries) {
      const auto prototype = entry->create();
      json.key(entry->type).beginObject();
      json.field("plugin", entry->plugin).field("summary", entry->summary);
      json.field("ticks", prototype->rateHz() > 0);
      json.key("fields").beginArray();
      for (const BaseField* f : prototype->fields()) {
        json.beginObject().field("name", f->name()).field("type", f->typeName()).field("default", f->defaultText());
        json.field("unit", std::string(f->info().unit)).field("range", f->rangeText());
        json.field("required", f->info().required).field("help", std::string(f->info().help));
        json.endObject();
      }
      json.endArray().endObject();
    }
    json.endObject();
    return true;
  }

  for (const ComponentEntry* entry : entries) {
    const auto prototype = entry->create();
    if (format == ReferenceFormat::Markdown) {
      out << "### " << entry->type << "\n\n";
      out << entry->summary << ". Plugin: `" << entry->plugin << "`"
          << (entry->plugin == "core" ? " (always available)" : "") << ".\n\n";
      out << "| field | type | default | unit | range | help |\n|---|---|---|---|---|---|\n";
      for (const BaseField* f : prototype->fields()) {
        out << "| `" << f->name() << "`" << (f->info().required ? " (required)" : "") << " | `"
            << markdownCell(f->typeName()) << "`"
            << " | " << markdownCell(f->defaultText()) << " | " << f->info().unit << " | "
            << markdownCell(f->rangeText()) << " | " << markdownCell(std::string(f->info().help)) << " |\n";
      }
      const std::vector<std::string> backends = registry.backendNames(entry->type);
      if (!backends.empty()) {
        out << "\nCollision back-ends (`backend`):";
        for (const std::string& name : backends) {
          const BackendEntry* b = registry.findBackend(entry->type, name);
          out << " `" << name << "` (plugin `" << b->plugin << "`: " << markdownCell(b->summary) << ")"
              << (name == backends.back() ? "." : ";");
        }
        out << "\n";
      }
      out << "\n";
    } else {
      out << entry->type << "  [plugin " << entry->plugin << "]\n  " << entry->summary << "\n";
      for (const std::string& name : registry.backendNames(entry->type))
        out << "  back-end " << name << "  [plugin " << registry.findBackend(entry->type, name)->plugin << "]\n      "
            << registry.findBackend(entry->type, name)->summary << "\n";
      for (const BaseField* f : prototype->fields()) {
        out << "  " << f->name() << " : " << f->typeName();
        if (!f->defaultText().empty()) out << " = " << f->defaultText();
        if (!f->info().unit.empty()) out << " " << f->info().unit;
        if (!f->rangeText().empty()) out << "  " << f->rangeText();
        if (f->info().required) out << "  (required)";
        out << "\n      " << f->info().help << "\n";
      }
      out << "\n";
    }
  }
  return true;
}

}  // namespace trephine::cli
