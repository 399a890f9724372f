#include "framework/geometry/ContactFrame.h"

#include <algorithm>
#include <numeric>


namespace trephine {

ContactFrame::TargetEntry* ContactFrame::entryOf(const ShellContactTarget& target) {
  for (TargetEntry& entry : m_targets)
    if (entry.target == &target) return &entry;
  return nullptr;
}

void ContactFrame::queries(ShellContactTarget& target) {
  if (!entryOf(target)) m_targets.push_back({&target, false, {}, {}});
}

size_t ContactFrame::addResponder(std::string path, std::span<ShellContactTarget* const> targets) {
  for (ShellContactTarget* target : targets)
    if (target) queries(*target);
  m_responders.push_back({std::move(path), nullptr, {}});
  return m_responders.size() - 1;
}

void ContactFrame::seal() {
  m_order.resize(m_responders.size());
  std::iota(m_order.begin(), m_order.end(), size_t{0});
  // By path, then by slot (paths are unique in a scene; the slot keeps the order total).
  std::sort(m_order.begin(), m_order.end(), [&](size_t a, size_t b) {
    const int order = m_responders[a].path.compare(m_responders[b].path);
    return order != 0 ? order < 0 : a < b;
  });
  for (TargetEntry& entry : m_targets) entry.responses.reserve(m_responders.size());
}

void ContactFrame::begin(double t) {
  m_t = t;
  for (TargetEntry& entry : m_targets) entry.begun = false;
  for (Responder& responder : m_responders) responder.target = nullptr;
}

TargetFrame ContactFrame::frameOf(ShellContactTarget& target) {
  TargetEntry* entry = entryOf(target);
  if (!entry) return {};
  if (!entry->begun) {
    entry->frame = target.beginFrame(m_t);
    entry->begun = true;
  }
  return entry->frame;
}

void ContactFrame::respond(size_t responder, ShellContactTarget& target, const ContactResponse& response) {
  if (responder >= m_responders.size() || !entryOf(target)) return;
  m_responders[responder].target = &target;
  m_responders[responder].response = response;
}

void ContactFrame::end() {
  for (TargetEntry& entry : m_targets) {
    entry.responses.clear();  // within the capacity seal() reserved
    for (const size_t slot : m_order)
      if (m_responders[slot].target == entry.target) entry.responses.push_back(m_responders[slot].response);
    entry.target->respond(m_t, entry.responses);
  }
}

}  // namespace trephine
