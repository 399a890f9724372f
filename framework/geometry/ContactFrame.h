#pragma once
// The contact stage of a haptic frame, owned by the rate group's step (the
// scheduler's, as Box2D's world step and MuJoCo's mj_step own theirs). Each
// frame:
//   1. begin    - the owner opens the frame; no target is begun yet;
//   2. frameOf  - the first member of the frame that asks for a target begins
//                 it (its latest shape taken, the cuts of the frame before
//                 applied); every later ask of the frame gets the same answer,
//                 so every tool sees one shape per frame;
//   3. respond  - each force renderer leaves its response (the force on the
//                 target, the cut) in its own slot;
//   4. end      - the owner hands each target all of its frame's responses in
//                 one call, in the order of the renderers' paths (the scene's
//                 ids, not the order of the file).
// A tool's queries depend only on the frame's shape and on its own memory
// (ContactMemory, owned by its proxy), and a target combines its responses in
// a fixed order, so no result depends on the order tools are listed in.
// Components join before the run (ContactFrameMember); a frame allocates
// nothing, locks nothing and throws nothing.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "framework/core/Interface.h"
#include "framework/geometry/ShellContactTarget.h"

namespace trephine {

class ContactFrame;

// A component whose tick queries contact targets or responds to them (a
// proxy, a force renderer, a warning) says which, once, before the run.
class TREPHINE_INTERFACE ContactFrameMember {
 public:
  virtual ~ContactFrameMember();
  virtual void joinContactFrame(ContactFrame& frame) = 0;
};

class ContactFrame {
 public:
  // Before the run (may allocate).
  // A member will ask for `target`'s frame.
  void queries(ShellContactTarget& target);
  // A member (its component path) will respond to some of `targets` each
  // frame; returns its slot, for respond(). Responses reach a target in the
  // order of the responders' paths.
  size_t addResponder(std::string path, std::span<ShellContactTarget* const> targets);
  // The responders in path order; call once every member joined.
  void seal();
  bool empty() const { return m_targets.empty(); }

  // Each frame.
  void begin(double t);
  // The target's frame (begun on the first ask of the frame). A target no
  // member declared gets an empty frame and is not begun.
  TargetFrame frameOf(ShellContactTarget& target);
  // The responder's response this frame, to `target` (one a frame; a second
  // replaces the first).
  void respond(size_t responder, ShellContactTarget& target, const ContactResponse& response);
  // Every declared target gets its frame's responses (none too: a deformable
  // target learns that the contacts ended), in one call.
  void end();

 private:
  struct TargetEntry {
    ShellContactTarget* target = nullptr;
    bool begun = false;
    TargetFrame frame;
    std::vector<ContactResponse> responses;  // this frame's, in responder order; capacity: the responders
  };
  struct Responder {
    std::string path;
    ShellContactTarget* target = nullptr;  // this frame's response went to it; null: none
    ContactResponse response;
  };
  TargetEntry* entryOf(const ShellContactTarget& target);

  std::vector<TargetEntry> m_targets;
  std::vector<Responder> m_responders;  // by slot
  std::vector<size_t> m_order;          // slots in path order
  double m_t = 0;
};

}  // namespace trephine
