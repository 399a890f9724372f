#pragma once
// The unit of a scene: a component has typed fields and links, is created by
// the registry from its XML tag, initialised once, and, when it has a `rate`
// field, ticked by the scheduler in the rate group of that rate.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Field.h"
#include "framework/core/FieldOwner.h"
#include "framework/core/Link.h"

namespace trephine {

class Node;
class InitContext;
class FinishContext;
class EventLog;
class ContactFrame;
struct RunPlan;

// Passed to every tick. `t` is the scheduled time of this call (s), the same
// in virtual and real time; `dt` the group period (s). `contacts`: the rate
// group's contact frame (framework/geometry/ContactFrame.h), which begins
// targets and takes responses for it; null outside a scheduler's step.
struct TickContext {
  double t = 0;
  double dt = 0;
  uint64_t frame = 0;
  EventLog* events = nullptr;
  ContactFrame* contacts = nullptr;
};

// A file a component will write into the run directory, and the field that
// names it (if any); `folder`: a folder of files the component fills as it runs.
struct OutputFile {
  std::string name;
  const BaseField* field = nullptr;
  bool folder = false;
};

// A named figure a component adds to its entry in summary.json ("rejected_non_finite": 3).
struct Counter {
  std::string name;
  double value = 0;
};

// A named text in a component's entry of summary.json (the collision back-end it used).
struct Fact {
  std::string name;
  std::string value;
};

// A block of its own at the top of summary.json (a contract of the brief, such
// as `resection`): its figures by dotted path ("removed_mm3.tumour" is
// "removed_mm3": {"tumour": ...}); with `toolsOn`, a "tools" object gives,
// for each tool whose frames touched that target (HapticFrame::target), its
// path length, its time in contact and its forces on it.
struct SummaryBlock {
  std::string name;
  std::vector<Counter> figures;
  const void* toolsOn = nullptr;
};

class Component : public FieldOwner {
 public:
  static constexpr std::string_view kTypeName = "Component";

  Component();
  ~Component() override;

  const std::string& typeName() const { return m_typeName; }
  // The `name` attribute, or the type name when none was given.
  const std::string& name() const;
  Node* node() const { return m_node; }
  // "/tool/device": node names from the root (excluded) down, then the component name.
  std::string path() const;

  // The component's tick rate in Hz, or 0 for a passive component (no `rate` field).
  double rateHz() const;
  // The named rate group beside the rate (the `group` field), "" for the rate's own.
  const std::string& rateGroup() const;
  bool isTicking() const { return rateHz() > 0; }

  // ---- life cycle, in this order --------------------------------------------
  // After every field and link is set: cross-field checks, file loading, channel
  // set-up. Throw std::runtime_error (or report through the context) on bad input.
  virtual void init(InitContext& context);
  // How long this component wants the run to last (s), e.g. a scripted path; 0 for no preference.
  virtual double preferredDuration() const { return 0; }
  // Once the run length is known: allocate every buffer the run will need.
  virtual void prepare(const RunPlan& plan);
  // Called by the scheduler at the component's rate. Must not allocate, lock, log or throw.
  virtual void tick(const TickContext& context);
  // After the run (also after an interrupt): write own outputs.
  virtual void finish(FinishContext& context);
  // Figures for this component's entry in summary.json.
  virtual void reportCounters(std::vector<Counter>& counters) const;
  // Texts for the same entry, e.g. {"backend", "native"}.
  virtual void reportFacts(std::vector<Fact>& facts) const { (void)facts; }
  // A block of summary.json of its own, or none (the default).
  virtual std::optional<SummaryBlock> summaryBlock() const { return std::nullopt; }
  // The files finish() will write, checked after init (plain names, none of the
  // run's own, no two alike) so that a bad name fails the load, not the end of a run.
  virtual void declareOutputs(std::vector<OutputFile>& outputs) const;

  // Set by the loader.
  void attach(Node* node, std::string typeName);

 private:
  Field<std::string> d_name{this, "name", "", {.help = "Name of the component, unique within its node"}};
  Node* m_node = nullptr;
  std::string m_typeName;
};

template <class T>
bool Link<T>::bind(Component* target) {
  m_target = dynamic_cast<T*>(target);
  m_component = m_target ? target : nullptr;
  return m_target != nullptr;
}

template <class T>
Component* Link<T>::boundComponent() const {
  return m_component;
}

}  // namespace trephine
