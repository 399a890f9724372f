#include "tools/trephine/PhantomCommand.h"

#include <iostream>

#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "framework/runtime/Simulation.h"

namespace trephine::cli {

// The phantoms come from the plugins, through the registry: each plugin that
// generates data registers a writer for the file names it writes.
int phantomCommand(const Arguments& arguments) {
  Registry registry;
  registerCoreComponents(registry);
  PluginLoader plugins;
  std::string loadErrors;
  for (const std::string& name : plugins.available())
    if (auto e = plugins.load(name, registry)) loadErrors += "trephine phantom: " + *e + "\n";

  if (arguments.positional.size() != 1 || !arguments.has("--out")) {
    std::cerr << loadErrors;
    for (const PhantomWriterEntry& writer : registry.phantomWriters()) {
      std::cerr << "usage: trephine phantom SPEC --out FILE";
      for (size_t i = 0; i < writer.suffixes.size(); ++i) std::cerr << (i ? "|FILE" : "") << writer.suffixes[i];
      std::cerr << (writer.canWriteRaw ? " [--raw]" : "") << "   (a " << writer.kind << ", plugin " << writer.plugin
                << ")\n";
    }
    for (const PhantomWriterEntry& writer : registry.phantomWriters())
      std::cerr << writer.kind << " phantoms:\n" << writer.help;
    return kUsage;
  }
  const std::string spec = arguments.positional[0];
  const std::string out = *arguments.get("--out");
  const PhantomWriterEntry* writer = registry.phantomWriterFor(out);
  if (!writer) {
    std::cerr << loadErrors << "trephine phantom: cannot tell what to write to '" << out << "': expected";
    bool first = true;
    for (const PhantomWriterEntry& w : registry.phantomWriters()) {
      std::cerr << (first ? " " : " or ");
      for (size_t i = 0; i < w.suffixes.size(); ++i) std::cerr << (i ? " or " : "") << w.suffixes[i];
      std::cerr << " (a " << w.kind << ")";
      first = false;
    }
    std::cerr << (first ? " a plugin that writes phantoms (none was found)" : "") << "\n";
    return kUsage;
  }
  if (arguments.has("--raw") && !writer->canWriteRaw) {
    std::cerr << "trephine phantom: --raw is for files a plugin can write uncompressed; a " << writer->kind
              << " is not (" << out << ")\n";
    return kUsage;
  }
  try {
    std::cout << out << ": " << writer->write(spec, out, arguments.has("--raw")) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "trephine phantom: " << e.what() << "\n";
    return kSceneError;
  }
  return kOk;
}

}  // namespace trephine::cli
