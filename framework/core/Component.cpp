#include "framework/core/Component.h"

#include "framework/core/Node.h"
#include "framework/core/Strings.h"

namespace trephine {

Component::Component() = default;
Component::~Component() = default;

const std::string& Component::name() const { return d_name->empty() ? m_typeName : d_name.value(); }

std::string Component::path() const {
  std::string p = m_node ? m_node->path() : "/";
  if (p.back() != '/') p += '/';
  return p + name();
}

double Component::rateHz() const {
  for (const BaseField* field : fields()) {
    if (const auto* rate = dynamic_cast<const RateField*>(field)) return rate->value();
  }
  return 0;
}

const std::string& Component::rateGroup() const {
  static const std::string none;
  for (const BaseField* field : fields()) {
    if (const auto* rate = dynamic_cast<const RateField*>(field)) return rate->group();
  }
  return none;
}

void Component::init(InitContext&) {}
void Component::prepare(const RunPlan&) {}
void Component::tick(const TickContext&) {}
void Component::finish(FinishContext&) {}
void Component::reportCounters(std::vector<Counter>&) const {}
void Component::declareOutputs(std::vector<OutputFile>&) const {}

void Component::attach(Node* node, std::string typeName) {
  m_node = node;
  m_typeName = std::move(typeName);
}

// ---- BaseLink ---------------------------------------------------------------

BaseLink::BaseLink(FieldOwner* owner, std::string_view name, std::string_view targetType, FieldInfo info)
    : BaseField(owner, name, info), m_targetType(targetType) {}

std::optional<std::string> BaseLink::parseAndStore(std::string_view text, const ParseContext&) {
  const std::string t(trim(text));
  if (t.size() < 2 || t[0] != '@') return "expected a link '@path' to a " + m_targetType + ", got " + visiblyQuoted(t);
  m_path = t.substr(1);
  return std::nullopt;
}

}  // namespace trephine
