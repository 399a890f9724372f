#include "framework/geometry/BackendBinding.h"

#include <algorithm>
#include <stdexcept>

#include "framework/core/Strings.h"

namespace trephine {

std::string missingBackendMessage(std::string_view name, std::string_view kind,
                                  const std::vector<std::string>& registered,
                                  const std::vector<std::string>& installed) {
  std::string known;
  for (const std::string& r : registered) known += (known.empty() ? "" : ", ") + r;
  std::string message = "no collision back-end \"" + std::string(name) + "\" for " + std::string(kind) +
                        " (registered: " + (known.empty() ? "none" : known) + ")";
  const auto isInstalled = [&](std::string_view plugin) {
    return std::find(installed.begin(), installed.end(), plugin) != installed.end();
  };
  if (isInstalled(name))
    return message + "; the plugin \"" + std::string(name) + "\" is installed: if it provides the back-end, add " +
           "<RequiredPlugin name=\"" + std::string(name) + "\"/> to the scene";
  std::vector<std::string> candidates = registered;
  candidates.insert(candidates.end(), installed.begin(), installed.end());
  if (const auto closest = closestMatch(name, candidates)) {
    message += ", did you mean \"" + *closest + "\"?";
    if (std::find(registered.begin(), registered.end(), *closest) == registered.end())
      message += " (a plugin of that name is installed: add <RequiredPlugin name=\"" + *closest + "\"/>)";
    return message;
  }
  std::string plugins;
  for (const std::string& p : installed) plugins += (plugins.empty() ? "" : ", ") + p;
  return message + "; no plugin of that name is installed either (installed: " + (plugins.empty() ? "none" : plugins) +
         ")";
}

void throwBackendFailure(const Component& target, const Field<std::string>& field, const std::exception& e) {
  throw std::runtime_error("collision back-end \"" + field.value() + "\" of " + target.path() + " failed: " + e.what());
}

}  // namespace trephine
