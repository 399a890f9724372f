#include "framework/scene/SceneLoader.h"

#include <algorithm>
#include <set>

#include "framework/core/Strings.h"
#include "framework/scene/Directives.h"
#include "framework/scene/IncludeExpander.h"
#include "framework/scene/ScenePaths.h"
#include "framework/scene/XmlTree.h"

namespace trephine {

namespace {

bool isValidName(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

// "a SurfaceTarget", "an ImplicitSurface".
std::string withArticle(const std::string& word) {
  const bool vowel = !word.empty() && std::string_view("AEIOUaeiou").find(word[0]) != std::string_view::npos;
  return (vowel ? "an " : "a ") + word;
}

std::string describe(const Component& c) { return c.typeName() + " '" + c.name() + "'"; }

}  // namespace

// State of one load.
struct SceneLoader::Build {
  SceneLoader& loader;
  Diagnostics& diagnostics;
  std::unique_ptr<Registry> catalog{};    // every available plugin, for "add <RequiredPlugin>" hints
  std::set<const BaseField*> rejected{};  // fields whose given value was invalid
  std::vector<std::string> failedPlugins{};
  std::set<std::pair<const Node*, std::string>> uncreated{};  // components that could not be created

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
      std::string searched;
      for (const auto& dir : loader.m_plugins.searchPath()) searched += (searched.empty() ? "" : ":") + dir.string();
      const std::string hint = didYouMean(name, loader.m_plugins.available());
      diagnostics.error(nameAttribute->valueAt,
                        "unknown plugin '" + name + "'" + (hint.empty() ? "" : hint + ";") + " no trephine_" + name +
                            ".so in " + (searched.empty() ? std::string("any directory") : searched) +
                            " (add its directory to TREPHINE_PLUGIN_PATH)");
      failedPlugins.push_back(name);
      return;
    }
    if (auto error = loader.m_plugins.load(name, loader.m_registry)) {
      diagnostics.error(e.at, *error);
      failedPlugins.push_back(name);
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
        diagnostics.error(a.nameAt,
                          "unknown attribute '" + a.name + "' of " + what + didYouMean(a.name, owner.fieldNames()));
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
        diagnostics.error(a ? a->valueAt : child.at, "duplicate name '" + name + "' in node '" + node.path() +
                                                         "' (first used at " + it->second->at.str() + ")" +
                                                         (a ? "" : "; give each a distinct name attribute"));
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
        // Links to it would only repeat this error.
        const XmlAttribute* name = child.attribute("name");
        uncreated.insert({&node, name ? name->value : child.tag});
        continue;
      }
      component->setLocation(child.at);
      component->attach(&node, child.tag);
      Component& added = node.addComponent(std::move(component));
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
    if (hint.empty() && !failedPlugins.empty()) {
      std::string plugins;
      for (const auto& p : failedPlugins) plugins += (plugins.empty() ? "'" : ", '") + p + "'";
      hint = " (perhaps from plugin " + plugins + ", which could not be loaded)";
    }
    diagnostics.error(e.at, "unknown component '" + e.tag + "'" + hint);
  }

  void resolveLinks(Node& node, Node& root) {
    for (const auto& component : node.components()) {
      for (BaseField* field : component->fields()) {
        auto* link = dynamic_cast<BaseLink*>(field);
        if (!link || !link->hasPath()) continue;
        const std::string what = "link " + link->name() + "=\"@" + link->path() + "\" of " + describe(*component);
        Component* target =
            resolveComponentPath(link->path(), node, root, link->location(), what, diagnostics, &uncreated);
        if (!target) continue;
        if (target == component.get()) {
          diagnostics.error(link->location(), what + " points to the component itself");
        } else if (!link->bind(target)) {
          diagnostics.error(link->location(), what + " points to " + describe(*target) + ", expected " +
                                                  withArticle(link->targetType()));
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
                                                       " (" + field->typeName() + ": " +
                                                       std::string(field->info().help) + ")");
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
    } else if (Node* node = findNodePath(path, root)) {
      // A node path is allowed too ("--set tool.units=mm" is valid but rarely useful).
      owner = node;
      what = "<Node> '" + node->path() + "'";
    } else {
      Component* c = resolveComponentPath(path, root, root, where, "--set", diagnostics);
      if (!c) return;
      owner = c;
      what = describe(*c);
    }
    BaseField* field = owner->findField(fieldName);
    if (!field) {
      diagnostics.error(where,
                        "unknown field '" + fieldName + "' of " + what + didYouMean(fieldName, owner->fieldNames()));
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
  XmlElement holder;
  holder.children.push_back(std::move(rootElement));
  expandIncludes(holder, file, diagnostics);
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

}  // namespace trephine
