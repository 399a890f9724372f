#include "framework/scene/SceneLoader.h"

#include <algorithm>
#include <set>

#include "framework/core/Strings.h"
#include "framework/scene/XmlTree.h"

namespace trephine {

namespace {

constexpr std::string_view kNodeTag = "Node";
constexpr std::string_view kPluginTag = "RequiredPlugin";
constexpr std::string_view kIncludeTag = "Include";
constexpr int kMaxIncludeDepth = 32;
// Two includes of a part that includes two of another, and so on, grow
// exponentially within the depth limit; a scene never needs this many.
constexpr int kMaxIncludes = 1000;

bool isValidName(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
         });
}

// Checks that an element has only the attributes in `allowed`.
void checkDirectiveAttributes(const XmlElement& e, const std::vector<std::string>& allowed, Diagnostics& d) {
  for (const XmlAttribute& a : e.attributes) {
    if (std::find(allowed.begin(), allowed.end(), a.name) == allowed.end())
      d.error(a.nameAt, "unknown attribute '" + a.name + "' of <" + e.tag + ">" + didYouMean(a.name, allowed));
  }
}

// "a SurfaceTarget", "an ImplicitSurface".
std::string withArticle(const std::string& word) {
  const bool vowel = !word.empty() && std::string_view("AEIOUaeiou").find(word[0]) != std::string_view::npos;
  return (vowel ? "an " : "a ") + word;
}

std::string describe(const Component& c) { return c.typeName() + " '" + c.name() + "'"; }

// A file being included, outermost first, to detect and show cycles.
struct IncludeFrame {
  std::filesystem::path canonical;
  std::string shown;  // as written in messages
};

}  // namespace

// State of one load.
struct SceneLoader::Build {
  SceneLoader& loader;
  Diagnostics& diagnostics;
  std::unique_ptr<Registry> catalog{};  // every available plugin, for "add <RequiredPlugin>" hints
  std::set<const BaseField*> rejected{};  // fields whose given value was invalid
  int includesRead = 0;

  // ---- includes -------------------------------------------------------------
  void expandIncludes(XmlElement& element, std::vector<IncludeFrame>& chain) {
    for (auto it = element.children.begin(); it != element.children.end();) {
      if (it->tag != kIncludeTag) {
        expandIncludes(*it, chain);
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
      chain.push_back({canonical, path.string()});
      XmlElement holder;  // lets expandIncludes replace an <Include> at the included file's root too
      holder.children.push_back(std::move(*included));
      expandIncludes(holder, chain);
      chain.pop_back();
      for (auto& child : holder.children) {
        it = element.children.insert(it, std::move(child));
        ++it;
      }
    }
  }

  // ---- plugins --------------------------------------------------------------
  void loadPlugins(const XmlElement& element) {
    for (const XmlElement& child : element.children) {
      if (child.tag == kPluginTag) {
        loadPlugin(child);
      } else {
        loadPlugins(child);
      }
    }
  }

  void loadPlugin(const XmlElement& e) {
    checkDirectiveAttributes(e, {"name"}, diagnostics);
    if (!e.children.empty()) diagnostics.error(e.children.front().at, "<RequiredPlugin> has no children");
    const XmlAttribute* nameAttribute = e.attribute("name");
    if (!nameAttribute || trim(nameAttribute->value).empty()) {
      diagnostics.error(e.at, "<RequiredPlugin> needs a name: <RequiredPlugin name=\"haptics\"/>");
      return;
    }
    const std::string name(trim(nameAttribute->value));
    auto& loaded = loader.m_loadedPlugins;
    if (std::find(loaded.begin(), loaded.end(), name) != loaded.end()) return;
    if (!loader.m_plugins.locate(name)) {
      diagnostics.error(nameAttribute->valueAt,
                        "unknown plugin '" + name + "'" + didYouMean(name, loader.m_plugins.available()));
      return;
    }
    if (auto error = loader.m_plugins.load(name, loader.m_registry)) {
      diagnostics.error(e.at, *error);
      return;
    }
    loaded.push_back(name);
  }

  const ComponentEntry* findInCatalog(const std::string& type) {
    if (!catalog) {
      catalog = std::make_unique<Registry>();
      for (const std::string& plugin : loader.m_plugins.available()) (void)loader.m_plugins.load(plugin, *catalog);
    }
    return catalog->find(type);
  }

  // ---- tree -----------------------------------------------------------------
  void assignAttributes(FieldOwner& owner, const XmlElement& e, const std::string& what) {
    for (const XmlAttribute& a : e.attributes) {
      BaseField* field = owner.findField(a.name);
      if (!field) {
        diagnostics.error(a.nameAt, "unknown attribute '" + a.name + "' of " + what + didYouMean(a.name, owner.fieldNames()));
        continue;
      }
      if (auto error = field->assign(a.value, ParseContext{e.baseDirectory}, a.valueAt)) {
        diagnostics.error(a.valueAt, "invalid " + a.name + " of " + what + ": " + *error);
        rejected.insert(field);  // given but invalid: not also "missing"
      }
    }
  }

  void checkName(const std::string& name, const XmlElement& e) {
    if (isValidName(name)) return;
    const XmlAttribute* a = e.attribute("name");
    diagnostics.error(a ? a->valueAt : e.at,
                      "invalid name '" + name + "': use letters, digits, '_' and '-' (no '/', '.' or spaces)");
  }

  void buildNode(const XmlElement& e, Node& node) {
    assignAttributes(node, e, "<Node>");
    if (node.parent() && !node.d_name.isSet()) diagnostics.error(e.at, "<Node> needs a name attribute");
    if (node.d_name.isSet()) checkName(node.name(), e);
    std::map<std::string, const XmlElement*> names;  // for duplicate detection
    const auto claimName = [&](const std::string& name, const XmlElement& child) {
      const auto [it, inserted] = names.emplace(name, &child);
      if (!inserted) {
        const XmlAttribute* a = child.attribute("name");
        diagnostics.error(a ? a->valueAt : child.at,
                          "duplicate name '" + name + "' in node '" + node.path() + "' (first used at " +
                              it->second->at.str() + ")" + (a ? "" : "; give each a distinct name attribute"));
      }
    };
    for (const XmlElement& child : e.children) {
      if (child.tag == kPluginTag) continue;  // loaded before the tree is built
      if (child.tag == kNodeTag) {
        auto childNode = std::make_unique<Node>(&node);
        childNode->setLocation(child.at);
        Node& added = node.addChild(std::move(childNode));
        buildNode(child, added);
        if (added.d_name.isSet()) claimName(added.name(), child);  // else already reported as unnamed
        continue;
      }
      auto component = loader.m_registry.create(child.tag);
      if (!component) {
        reportUnknownComponent(child);
        continue;
      }
      component->setLocation(child.at);
      component->attach(&node, child.tag);
      Component& added = node.addComponent(std::move(component));
      // The name first, so that messages about the other attributes name the component.
      if (const XmlAttribute* name = child.attribute("name"))
        (void)added.findField("name")->assign(name->value, ParseContext{child.baseDirectory}, name->valueAt);
      if (!child.children.empty())
        diagnostics.error(child.children.front().at, "<" + child.tag + "> is a component and has no child elements");
      // The name first, so that messages about the other attributes name the component.
      if (const XmlAttribute* name = child.attribute("name")) {
        XmlElement nameOnly;
        nameOnly.baseDirectory = child.baseDirectory;
        nameOnly.attributes.push_back(*name);
        assignAttributes(added, nameOnly, describe(added));
      }
      XmlElement others = child;
      std::erase_if(others.attributes, [](const XmlAttribute& a) { return a.name == "name"; });
      assignAttributes(added, others, describe(added));
      if (child.attribute("name")) checkName(added.name(), child);
      claimName(added.name(), child);
    }
  }

  void reportUnknownComponent(const XmlElement& e) {
    if (const ComponentEntry* entry = findInCatalog(e.tag)) {
      diagnostics.error(e.at, "component '" + e.tag + "' is provided by plugin '" + entry->plugin +
                                  "', which this scene does not load; add <RequiredPlugin name=\"" + entry->plugin +
                                  "\"/> near the top of the scene");
      return;
    }
    std::vector<std::string> candidates = loader.m_registry.typeNames();
    if (catalog) {
      for (auto& name : catalog->typeNames()) candidates.push_back(name);
    }
    candidates.emplace_back(kNodeTag);
    candidates.emplace_back(kPluginTag);
    candidates.emplace_back(kIncludeTag);
    std::string hint = didYouMean(e.tag, candidates);
    if (!hint.empty()) {
      const std::string suggestion = *closestMatch(e.tag, candidates);
      const ComponentEntry* entry = loader.m_registry.find(suggestion);
      if (!entry && catalog) entry = catalog->find(suggestion);
      if (entry && !loader.m_registry.find(suggestion))
        hint += " (in plugin '" + entry->plugin + "': add <RequiredPlugin name=\"" + entry->plugin + "\"/>)";
    }
    diagnostics.error(e.at, "unknown component '" + e.tag + "'" + hint);
  }

  // ---- paths and links ------------------------------------------------------
  // Resolves "a/b/c" from `start` (or the root when it starts with '/'): the
  // leading segments are nodes, the last a component. Reports at `where`.
  Component* resolveComponent(std::string_view path, Node& start, Node& root, const SourceLocation& where,
                              const std::string& what) {
    Node* node = &start;
    if (path.starts_with('/')) {
      node = &root;
      path.remove_prefix(1);
    }
    std::vector<std::string_view> segments;
    size_t begin = 0;
    while (begin <= path.size()) {
      const size_t slash = path.find('/', begin);
      const size_t end = slash == std::string_view::npos ? path.size() : slash;
      segments.push_back(path.substr(begin, end - begin));
      if (slash == std::string_view::npos) break;
      begin = slash + 1;
    }
    for (size_t i = 0; i < segments.size(); ++i) {
      const std::string segment(segments[i]);
      const bool last = i + 1 == segments.size();
      if (segment.empty() || segment == ".") {
        if (last) break;
        continue;
      }
      if (segment == "..") {
        if (!node->parent()) {
          diagnostics.error(where, what + ": '..' goes above the root node");
          return nullptr;
        }
        node = node->parent();
        continue;
      }
      if (last) {
        if (Component* c = node->findComponent(segment)) return c;
        if (node->findChild(segment)) {
          diagnostics.error(where, what + ": '" + segment + "' is a node, not a component");
          return nullptr;
        }
      } else if (Node* child = node->findChild(segment)) {
        node = child;
        continue;
      }
      diagnostics.error(where, what + ": no " + (last ? "component" : "node") + " '" + segment + "' in node '" +
                                   node->path() + "'" + didYouMean(segment, node->memberNames()));
      return nullptr;
    }
    diagnostics.error(where, what + ": the path names no component");
    return nullptr;
  }

  void resolveLinks(Node& node, Node& root) {
    for (const auto& component : node.components()) {
      for (BaseField* field : component->fields()) {
        auto* link = dynamic_cast<BaseLink*>(field);
        if (!link || !link->hasPath()) continue;
        const std::string what = "link " + link->name() + "=\"@" + link->path() + "\" of " + describe(*component);
        Component* target = resolveComponent(link->path(), node, root, link->location(), what);
        if (!target) continue;
        if (target == component.get()) {
          diagnostics.error(link->location(), what + " points to the component itself");
        } else if (!link->bind(target)) {
          diagnostics.error(link->location(), what + " points to " + describe(*target) + ", expected " + withArticle(link->targetType()) +
                                                  link->targetType());
        }
      }
    }
    for (const auto& child : node.children()) resolveLinks(*child, root);
  }

  void checkRequired(Node& node) {
    for (const auto& component : node.components()) {
      for (BaseField* field : component->fields()) {
        if (field->info().required && !field->isSet() && !rejected.count(field))
          diagnostics.error(component->location(), "missing required " + field->name() + " of " + describe(*component) +
                                                       " (" + field->typeName() + ": " + std::string(field->info().help) + ")");
      }
    }
    for (const auto& child : node.children()) checkRequired(*child);
  }

  // ---- overrides --------------------------------------------------------------
  void applyOverride(const std::string& text, Node& root) {
    const SourceLocation where{"--set " + text, 0, 0};
    const size_t equals = text.find('=');
    const size_t dot = equals == std::string::npos ? std::string::npos : text.rfind('.', equals);
    if (equals == std::string::npos || dot == std::string::npos || dot == 0) {
      diagnostics.error(where, "expected path.field=value, e.g. --set tool/force.stiffness=1.5");
      return;
    }
    const std::string path = text.substr(0, dot);
    const std::string fieldName = text.substr(dot + 1, equals - dot - 1);
    const std::string value = text.substr(equals + 1);
    FieldOwner* owner = nullptr;
    std::string what;
    if (path == "/" || path == "root") {
      owner = &root;
      what = "<Node> '/'";
    } else if (Node* node = findNode(path, root)) {
      // A node path is allowed too ("--set tool.units=mm" is valid but rarely useful).
      owner = node;
      what = "<Node> '" + node->path() + "'";
    } else {
      Component* c = resolveComponent(path, root, root, where, "--set");
      if (!c) return;
      owner = c;
      what = describe(*c);
    }
    BaseField* field = owner->findField(fieldName);
    if (!field) {
      diagnostics.error(where, "unknown field '" + fieldName + "' of " + what + didYouMean(fieldName, owner->fieldNames()));
      return;
    }
    if (field->name() == "name") {
      diagnostics.error(where, "--set cannot rename a component (links would change meaning)");
      return;
    }
    std::error_code ec;
    if (auto error = field->assign(value, ParseContext{std::filesystem::current_path(ec)}, where)) {
      diagnostics.error(where, "invalid " + fieldName + " of " + what + ": " + *error);
      rejected.insert(field);
    }
  }

  // The node at `path` from the root, or nullptr (quietly: the path may name a component).
  static Node* findNode(std::string_view path, Node& root) {
    Node* node = &root;
    while (!path.empty()) {
      const size_t slash = path.find('/');
      const std::string_view segment = path.substr(0, slash);
      path = slash == std::string_view::npos ? std::string_view() : path.substr(slash + 1);
      if (segment.empty() || segment == ".") continue;
      node = segment == ".." ? node->parent() : node->findChild(segment);
      if (!node) return nullptr;
    }
    return node;
  }
};

std::unique_ptr<Scene> SceneLoader::loadFile(const std::filesystem::path& file, Diagnostics& diagnostics,
                                             const std::vector<std::string>& overrides) {
  auto root = readXmlFile(file, SourceLocation{file.string(), 0, 0}, diagnostics);
  if (!root) return nullptr;
  return build(std::move(*root), file, diagnostics, overrides);
}

std::unique_ptr<Scene> SceneLoader::loadString(std::string_view xml, const std::string& fileName,
                                               Diagnostics& diagnostics, const std::vector<std::string>& overrides) {
  const std::filesystem::path file(fileName);
  auto root = parseXml(xml, fileName, file.parent_path(), diagnostics);
  if (!root) return nullptr;
  return build(std::move(*root), file, diagnostics, overrides);
}

std::unique_ptr<Scene> SceneLoader::build(XmlElement rootElement, const std::filesystem::path& file,
                                          Diagnostics& diagnostics, const std::vector<std::string>& overrides) {
  Build b{.loader = *this, .diagnostics = diagnostics};
  std::vector<IncludeFrame> chain;
  std::error_code ec;
  chain.push_back({std::filesystem::weakly_canonical(file, ec), file.string()});

  XmlElement holder;
  holder.children.push_back(std::move(rootElement));
  b.expandIncludes(holder, chain);
  if (holder.children.size() != 1) {
    if (!diagnostics.hasErrors()) diagnostics.error({file.string(), 1, 1}, "the scene has no root <Node>");
    return nullptr;
  }
  XmlElement& rootXml = holder.children.front();
  if (rootXml.tag != kNodeTag) {
    diagnostics.error(rootXml.at, "the root element of a scene is <Node>, found <" + rootXml.tag + ">");
    return nullptr;
  }
  b.loadPlugins(rootXml);

  auto root = std::make_unique<Node>();
  root->setLocation(rootXml.at);
  b.buildNode(rootXml, *root);
  for (const std::string& text : overrides) b.applyOverride(text, *root);
  b.checkRequired(*root);
  b.resolveLinks(*root, *root);
  if (diagnostics.hasErrors()) return nullptr;
  return std::make_unique<Scene>(std::move(root), file, m_loadedPlugins);
}

// ---- Scene ------------------------------------------------------------------

std::vector<Component*> Scene::components() const {
  std::vector<Component*> list;
  m_root->collectComponents(list);
  return list;
}

Component* Scene::findComponent(std::string_view path) const {
  if (path.starts_with('/')) path.remove_prefix(1);
  for (Component* c : components()) {
    if (std::string_view(c->path()).substr(1) == path) return c;
  }
  return nullptr;
}

}  // namespace trephine
