#include "framework/scene/IncludeExpander.h"

#include <algorithm>
#include <string>
#include <vector>

#include "framework/scene/Directives.h"

namespace trephine {

namespace {

constexpr int kMaxIncludeDepth = 32;
// Two includes of a part that includes two of another, and so on, grow
// exponentially within the depth limit; a scene never needs this many.
constexpr int kMaxIncludes = 1000;

// A file being included, outermost first, to detect and show cycles.
struct IncludeFrame {
  std::filesystem::path canonical;
  std::string shown;  // as written in messages
};

void markIncludedFrom(XmlElement& element, const std::string& from) {
  element.at.includedFrom = from;
  for (XmlAttribute& a : element.attributes) a.nameAt.includedFrom = a.valueAt.includedFrom = from;
  for (XmlElement& child : element.children) markIncludedFrom(child, from);
}

struct Expander {
  Diagnostics& diagnostics;
  int includesRead = 0;

  void expand(XmlElement& element, std::vector<IncludeFrame>& chain) {
    for (auto it = element.children.begin(); it != element.children.end();) {
      if (it->tag != kIncludeTag) {
        expand(*it, chain);
        ++it;
        continue;
      }
      const XmlElement include = std::move(*it);
      it = element.children.erase(it);
      checkDirectiveAttributes(include, {"file"}, diagnostics);
      const XmlAttribute* file = include.attribute("file");
      if (!file || trim(file->value).empty()) {
        diagnostics.error(include.at, "<Include> needs a file attribute: <Include file=\"part.xml\"/>");
        continue;
      }
      std::filesystem::path path = std::filesystem::path(std::string(trim(file->value)));
      if (path.is_relative()) path = include.baseDirectory / path;
      path = path.lexically_normal();
      std::error_code ec;
      auto canonical = std::filesystem::weakly_canonical(path, ec);
      if (ec) canonical = path;  // an empty path would match every other unresolvable one
      const auto cycleStart = std::find_if(chain.begin(), chain.end(),
                                           [&](const IncludeFrame& frame) { return frame.canonical == canonical; });
      if (cycleStart != chain.end()) {
        std::string cycle;
        for (auto frame = cycleStart; frame != chain.end(); ++frame) cycle += frame->shown + " -> ";
        diagnostics.error(file->valueAt, "include cycle: " + cycle + path.string());
        continue;
      }
      if (static_cast<int>(chain.size()) >= kMaxIncludeDepth) {
        diagnostics.error(file->valueAt, "includes nested deeper than " + std::to_string(kMaxIncludeDepth));
        continue;
      }
      if (++includesRead > kMaxIncludes) {
        if (includesRead == kMaxIncludes + 1)
          diagnostics.error(file->valueAt, "more than " + std::to_string(kMaxIncludes) + " includes in one scene");
        continue;
      }
      auto included = readXmlFile(path, file->valueAt, diagnostics);
      if (!included) continue;
      // Every position in the included text says where it was included, so that a part
      // included twice gives two distinguishable errors.
      const std::string from = file->valueAt.str() +
                               (file->valueAt.includedFrom.empty() ? "" : " <- " + file->valueAt.includedFrom);
      markIncludedFrom(*included, from);
      chain.push_back({canonical, path.string()});
      XmlElement holder;  // lets expand() replace an <Include> at the included file's root too
      holder.children.push_back(std::move(*included));
      expand(holder, chain);
      chain.pop_back();
      for (auto& child : holder.children) {
        it = element.children.insert(it, std::move(child));
        ++it;
      }
    }
  }
};

}  // namespace

void expandIncludes(XmlElement& holder, const std::filesystem::path& sceneFile, Diagnostics& diagnostics) {
  std::vector<IncludeFrame> chain;
  std::error_code ec;
  chain.push_back({std::filesystem::weakly_canonical(sceneFile, ec), sceneFile.string()});
  Expander{diagnostics}.expand(holder, chain);
}

}  // namespace trephine
