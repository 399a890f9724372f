// A TetraBrain whose nodes move: the grids stay those of the rest shape (boxes
// grown by the displacement margin), so every query must give exactly what the
// same shape gives as a rigid mesh, within the margin and beyond it. The
// reaction on the nodes sums to the contact force and acts where it acts.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <thread>

#include "framework/core/ChannelHub.h"
#include "framework/core/Diagnostics.h"
#include "framework/geometry/ContactFrame.h"
#include "tests/plugins/tetra_brain/TetTestShapes.h"
#include "tests/support/AllocationCounter.h"
#include "tests/support/BrainProbe.h"
#include "tests/support/TestSupport.h"

namespace trephine::tetra {
namespace {

using shapes::cubeBrain;
using shapes::pressing;
using shapes::sphereShell;

// Vertical spherical wave from (0, 0, 100): amplitude A (mm), wavelength 120 mm, at phase `phase`.
std::vector<Vec3> waved(const std::vector<Vec3>& rest, double A, double phase) {
  std::vector<Vec3> moved = rest;
  for (Vec3& p : moved) p.z() += A * std::sin(2 * std::numbers::pi * (p - Vec3(0, 0, 100)).norm() / 120.0 - phase);
  return moved;
}

// A brain following a deformation fed by hand through a channel.
struct FollowingBrain {
  Component producer;
  ChannelHub hub;
  TetraBrain brain;
  Channel<NodePositions>* channel = nullptr;
  uint64_t step = 0;

  explicit FollowingBrain(int cells) {
    cubeBrain(brain, cells);
    channel = &hub.publish<NodePositions>(producer, kNodePositionsChannel);
    EXPECT_FALSE(brain.followDeformation(producer, hub).has_value());
  }
  void moveTo(const std::vector<Vec3>& positions, double bound) {
    NodePositions frame;
    frame.step = ++step;
    frame.positions = positions;
    frame.displacementBound = bound;
    channel->publish(frame);
    brain.beginFrame(1e-3 * double(step));
  }
};

void expectSameContact(const ShellContact& a, const ShellContact& b, const std::string& where) {
  EXPECT_EQ(a.points, b.points) << where;
  EXPECT_EQ(a.primitives, b.primitives) << where;
  EXPECT_NEAR(a.penetration, b.penetration, 1e-9) << where;
  EXPECT_NEAR((a.normal - b.normal).norm(), 0.0, 1e-9) << where;
}

// The visible-overlap check (the proxy's pop-through proof) skips locating
// the inset points when no boundary face comes within their reach of an
// outside centre: it must answer as locating each of them would.
TEST(DeformingBrainTest, TheOverlapCheckAnswersAsLocatingEveryInsetPoint) {
  const std::vector<ShellPoint> shell = sphereShell(2.5, 266);
  FollowingBrain following(22);
  ContactMemory memory_following_brain_shell = following.brain.reserveShell(shell);
  const NativeTetBackend& native = shapes::native(following.brain);
  const double margin = native.displacementMargin();
  const double inset = 10 * following.brain.contactDepth();
  const std::vector<Vec3> rest = following.brain.mesh().nodes;
  int overlapping = 0, clear = 0;
  for (const double amplitude : {0.0, 0.5 * margin, 2.5 * margin}) {
    following.moveTo(waved(rest, amplitude, 1.0), amplitude);
    for (const Vec3& xy : {Vec3(0, 0, 0), Vec3(31.4, -12.9, 0), Vec3(97.9, 3, 0), Vec3(100.5, 100.5, 0)}) {
      const double top = 100 + amplitude * std::sin(2 * std::numbers::pi * xy.norm() / 120.0 - 1.0);
      for (double press = -1.0; press <= 3.0; press += 0.05) {
        const Pose pose{xy + Vec3(0, 0, top + 2.5 - press), Quat::Identity()};
        bool expected = native.locate(pose.position) >= 0;
        for (const ShellPoint& p : shell) {
          const double pull = std::min(inset, p.position.norm());
          expected = expected || native.locate(pose.position + p.position + pull * p.inwardNormal) >= 0;
        }
        EXPECT_EQ(following.brain.overlaps(pose, shell), expected)
            << "amplitude " << amplitude << " at " << xy.transpose() << " press " << press;
        (expected ? overlapping : clear) += 1;
      }
    }
  }
  EXPECT_GT(overlapping, 100);  // both answers were asked for, near the surface
  EXPECT_GT(clear, 100);
}

TEST(DeformingBrainTest, EveryQueryMatchesTheSameShapeBuiltAsARigidMesh) {
  const std::vector<ShellPoint> shell = sphereShell(2.5, 266);
  FollowingBrain following(22);  // 9 mm cells, average edge about 11 mm: auto margin about 2.8 mm
  ContactMemory memory_following_brain_shell = following.brain.reserveShell(shell);
  const double margin = shapes::native(following.brain).displacementMargin();
  ASSERT_GT(margin, 2.0);
  const std::vector<Vec3> rest = following.brain.mesh().nodes;
  // Within the margin (one grid cell per point) and far beyond it (widened queries).
  for (const double amplitude : {0.5 * margin, 2.5 * margin}) {
    for (const double phase : {0.0, 1.0, 2.5}) {
      const std::vector<Vec3> moved = waved(rest, amplitude, phase);
      following.moveTo(moved, amplitude);
      TetMesh shape = following.brain.mesh();
      shape.nodes = moved;
      TetraBrain rigid;
      rigid.setMesh(shape);
      ASSERT_EQ(rigid.report().invertedTets, 0u);
      ContactMemory memory_rigid_shell = rigid.reserveShell(shell);
      for (const Vec3& xy : {Vec3(0, 0, 0), Vec3(31.4, -12.9, 0), Vec3(-70, 55, 0), Vec3(97.9, 3, 0)}) {
        const double top = 100 + amplitude * std::sin(2 * std::numbers::pi * xy.norm() / 120.0 - phase);
        for (const double press : {-0.5, 0.4, 1.3, 3.0}) {
          const Pose pose{xy + Vec3(0, 0, top + 2.5 - press), Quat::Identity()};
          const std::string where = "amplitude " + std::to_string(amplitude) + " phase " + std::to_string(phase) +
                                    " at " + std::to_string(xy.x()) + "," + std::to_string(xy.y()) + " press " +
                                    std::to_string(press);
          expectSameContact(following.brain.collide(pose, shell, false, memory_following_brain_shell),
                            rigid.collide(pose, shell, false, memory_rigid_shell), where);
          EXPECT_EQ(following.brain.overlaps(pose, shell), rigid.overlaps(pose, shell)) << where;
          EXPECT_EQ(shapes::native(following.brain).locate(pose.position), shapes::native(rigid).locate(pose.position))
              << where;
          SweepQuery sweep;
          sweep.from = pose.position + Vec3(0.3, -0.2, 6.0);
          sweep.to = pose.position;
          sweep.leadingRadius = 2.5;
          const SweepResult a = following.brain.sweep(sweep), b = rigid.sweep(sweep);
          EXPECT_EQ(a.blocked, b.blocked) << where;
          EXPECT_NEAR(a.freeFraction, b.freeFraction, 1e-12) << where;
          Vec3 na, nb;
          EXPECT_NEAR(shapes::native(following.brain).depthBelowSurface(pose.position, na),
                      shapes::native(rigid).depthBelowSurface(pose.position, nb), 1e-9)
              << where;
        }
      }
    }
  }
  EXPECT_EQ(test::counter(following.brain, "frames_beyond_margin"), 3.0)
      << "the three frames of the larger amplitude widened the queries";
}

// A diverging FEM publishes nodes as far from rest as the mesh is large
// before it is reset. Widening every query by that scanned the whole grid for
// each point (seconds a frame); the widening is capped at half an average
// edge (or a cell, when larger), counted, and where nothing moved the
// answers stay those of the shape itself.
TEST(DeformingBrainTest, AShapeFarBeyondTheGridsWidensTheQueriesByHalfAnEdgeAtMost) {
  const std::vector<ShellPoint> shell = sphereShell(2.5, 266);
  FollowingBrain following(22);
  ContactMemory memory_following_brain_shell = following.brain.reserveShell(shell);
  const NativeTetBackend& native = shapes::native(following.brain);
  std::vector<Vec3> flung = following.brain.mesh().nodes;
  for (Vec3& p : flung)
    if (p.x() < -80) p.x() -= 150;  // the far side of the cube, thrown 150 mm further out
  following.moveTo(flung, 150.0);
  const double cell = test::counter(following.brain, "cell_size_mm");
  EXPECT_EQ(test::counter(following.brain, "frames_widening_capped"), 1.0);
  EXPECT_DOUBLE_EQ(native.queryWidening(), std::max(cell, 0.5 * native.averageEdge()));
  TetraBrain rest;
  cubeBrain(rest, 22);
  ContactMemory memory_rest_shell = rest.reserveShell(shell);
  for (const Vec3& xy : {Vec3(0, 0, 0), Vec3(31.4, -12.9, 0), Vec3(60, 55, 0)})
    for (const double press : {-0.5, 1.3, 3.0}) {
      const Pose pose{xy + Vec3(0, 0, 100 + 2.5 - press), Quat::Identity()};
      const std::string where =
          "at " + std::to_string(xy.x()) + "," + std::to_string(xy.y()) + " press " + std::to_string(press);
      expectSameContact(following.brain.collide(pose, shell, false, memory_following_brain_shell),
                        rest.collide(pose, shell, false, memory_rest_shell), where);
      EXPECT_EQ(following.brain.overlaps(pose, shell), rest.overlaps(pose, shell)) << where;
    }
}

TEST(DeformingBrainTest, PositionsOfAnotherSizeAreIgnoredAndCounted) {
  FollowingBrain following(7);
  const std::vector<Vec3> rest = following.brain.mesh().nodes;
  following.moveTo(waved(rest, 1.0, 0.3), 1.0);
  EXPECT_NE(following.brain.node(5), rest[5]);
  following.moveTo(std::vector<Vec3>(rest.size() - 1, Vec3::Zero()), 1.0);
  EXPECT_EQ(following.brain.node(5), rest[5]) << "back to the rest shape, never a slot the writer owns";
  EXPECT_EQ(test::counter(following.brain, "rejected_position_frames"), 1.0);
}

TEST(DeformingBrainTest, SpreadNodeForcesSumToTheContactForceOverMoreNodes) {
  // forceSpread: the same force shared among the boundary nodes within 20 mm
  // of the pressed ones (the cube's cells are 9 mm), its sum kept, its centre
  // where the pressed nodes' was (the top face is flat and evenly meshed).
  const auto publish = [](double spread, std::vector<NodeForce>& out, Vec3& centre) {
    ChannelHub hub;
    TetraBrain brain;
    if (spread > 0) {
      ASSERT_TRUE(brain.findField("forceSpread")->assign(std::to_string(spread), {}, {}) == std::nullopt);
    }
    cubeBrain(brain, 22);
    brain.connectChannels(hub);
    ChannelReader<NodeForces> reader = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
    const std::vector<ShellPoint> shell = sphereShell(2.5, 266);
    ContactMemory memory_brain_shell = brain.reserveShell(shell);
    brain.prepare(RunPlan{});
    const ShellContact contact =
        brain.collide({Vec3(13.1, -4.2, 100 + 2.5 - 0.8), Quat::Identity()}, shell, false, memory_brain_shell);
    ASSERT_GT(contact.points, 10);
    shapes::respondAlone(brain, pressing(1.0, Vec3(0, 0, -0.3), contact.sites));
    ASSERT_TRUE(reader.fetch());
    out = reader.read().forces;
    // The counter of the largest frame, on either path (spread or not).
    EXPECT_EQ(test::counter(brain, "largest_node_force_count"), double(out.size()));
    centre = Vec3::Zero();
    for (const NodeForce& f : out) centre += (f.force.z() / -0.3) * brain.node(f.node);
  };
  std::vector<NodeForce> pressed, spread;
  Vec3 pressedCentre, spreadCentre;
  publish(0, pressed, pressedCentre);
  publish(20, spread, spreadCentre);
  ASSERT_FALSE(spread.empty());
  Vec3 sum = Vec3::Zero();
  double largest = 0;
  for (const NodeForce& f : spread) {
    sum += f.force;
    largest = std::max(largest, f.force.norm());
  }
  EXPECT_NEAR((sum - Vec3(0, 0, -0.3)).norm(), 0.0, 1e-12);
  EXPECT_GT(spread.size(), 3 * pressed.size());
  double pressedLargest = 0;
  for (const NodeForce& f : pressed) pressedLargest = std::max(pressedLargest, f.force.norm());
  EXPECT_LT(largest, 0.5 * pressedLargest) << "no node carries most of the force";
  EXPECT_LT((spreadCentre - pressedCentre).head<2>().norm(), 3.0) << "mm, on a 9 mm mesh";
}

// Two tools on the brain in one frame: the node forces published for the
// frame carry both forces, each where it acts, and are the same to the bit
// whichever tool queried first. A tool's sites stay its own (its memory)
// while the other tool queries.
TEST(DeformingBrainTest, TwoToolsForcesAddUpWhicheverQueriesFirst) {
  const std::vector<ShellPoint> left = sphereShell(2.5, 266), right = sphereShell(2.0, 200);
  const Pose leftPose{Vec3(10.0, -4.2, 100 + 2.5 - 0.8), Quat::Identity()};
  const Pose rightPose{Vec3(13.5, -2.0, 100 + 2.0 - 0.6), Quat::Identity()};
  const Vec3 leftForce(0.05, -0.02, -0.3), rightForce(-0.03, 0.04, -0.2);  // N, on the brain
  const auto published = [&](bool leftFirst) {
    ChannelHub hub;
    TetraBrain brain;
    cubeBrain(brain, 22);
    brain.connectChannels(hub);
    ChannelReader<NodeForces> reader = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
    ContactMemory memory_brain_left = brain.reserveShell(left);
    ContactMemory memory_brain_right = brain.reserveShell(right);
    brain.prepare(RunPlan{});
    brain.beginFrame(0.5);
    // Both query before either responds (two proxies, then two force
    // feedbacks), each with its own memory; the responses come in the contact
    // frame's order (the renderers' paths), one call.
    ShellContact l, r;
    if (leftFirst) {
      l = brain.collide(leftPose, left, false, memory_brain_left);
      r = brain.collide(rightPose, right, false, memory_brain_right);
    } else {
      r = brain.collide(rightPose, right, false, memory_brain_right);
      l = brain.collide(leftPose, left, false, memory_brain_left);
    }
    EXPECT_GT(l.points, 5);
    EXPECT_GT(r.points, 5);
    const std::array<ContactResponse, 2> responses = {pressing(0.5, leftForce, l.sites),
                                                      pressing(0.5, rightForce, r.sites)};
    brain.respond(0.5, responses);
    EXPECT_TRUE(reader.fetch());
    return reader.read().forces;
  };
  const std::vector<NodeForce> leftFirst = published(true), rightFirst = published(false);
  Vec3 sum = Vec3::Zero();
  for (const NodeForce& f : leftFirst) sum += f.force;
  EXPECT_NEAR((sum - (leftForce + rightForce)).norm(), 0.0, 1e-12) << "both tools' forces reach the mesh";
  ASSERT_EQ(leftFirst.size(), rightFirst.size());
  for (size_t i = 0; i < leftFirst.size(); ++i) {
    EXPECT_EQ(leftFirst[i].node, rightFirst[i].node);
    EXPECT_EQ(leftFirst[i].force, rightFirst[i].force) << "node " << leftFirst[i].node;
  }
}

// In real time the FEM takes the node forces on its own thread, one value a
// tick: each value it can take is one whole frame's sum of every tool's
// force, never a frame with only some of its tools' (the contact frame hands
// the brain all of a frame's responses in one call, published once). A
// reader on another thread checks every value it takes against the frame's
// total, while the haptic thread runs frames of two tools whose forces change
// every frame.
TEST(DeformingBrainTest, AReaderOnAnotherThreadTakesOnlyWholeFramesOfNodeForces) {
  ChannelHub hub;
  TetraBrain brain;
  cubeBrain(brain, 22);
  brain.connectChannels(hub);
  ChannelReader<NodeForces> reader = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
  const std::vector<ShellPoint> left = sphereShell(2.5, 266), right = sphereShell(2.0, 200);
  ContactMemory leftMemory = brain.reserveShell(left), rightMemory = brain.reserveShell(right);
  brain.prepare(RunPlan{});
  ContactFrame frame;
  ShellContactTarget* targets[] = {&brain};
  const size_t leftSlot = frame.addResponder("/left/force", targets);
  const size_t rightSlot = frame.addResponder("/right/force", targets);
  frame.seal();
  const Pose leftPose{Vec3(10.0, -4.2, 100 + 2.5 - 0.8), Quat::Identity()};
  const Pose rightPose{Vec3(13.5, -2.0, 100 + 2.0 - 0.6), Quat::Identity()};
  // N on the brain in frame k: each tool's own rhythm, so that a value with
  // one tool's force alone (or another frame's) never sums to the total.
  const auto leftForce = [](int k) -> Vec3 { return Vec3(0.05, -0.02, -0.3) * (1 + k % 5); };
  const auto rightForce = [](int k) -> Vec3 { return Vec3(-0.03, 0.04, -0.2) * (1 + k % 3); };
  constexpr int kFrames = 20000;
  std::atomic<bool> done{false};
  std::atomic<int> taken{0}, partial{0};
  std::thread fem([&] {
    while (!done.load()) {
      if (!reader.fetch()) continue;
      const NodeForces& value = reader.read();
      if (value.forces.empty()) continue;
      const int k = int(std::lround(value.t * 1e4));
      Vec3 sum = Vec3::Zero();
      for (const NodeForce& f : value.forces) sum += f.force;
      ++taken;
      if ((sum - (leftForce(k) + rightForce(k))).norm() > 1e-9) ++partial;
    }
  });
  for (int k = 1; k <= kFrames; ++k) {
    const double t = k * 1e-4;
    frame.begin(t);
    frame.frameOf(brain);
    const ShellContact l = brain.collide(leftPose, left, false, leftMemory);
    const ShellContact r = brain.collide(rightPose, right, false, rightMemory);
    frame.respond(leftSlot, brain, pressing(t, leftForce(k), l.sites));
    frame.respond(rightSlot, brain, pressing(t, rightForce(k), r.sites));
    frame.end();
  }
  done = true;
  fem.join();
  EXPECT_GT(taken.load(), 100) << "the reader took values while the frames ran";
  EXPECT_EQ(partial.load(), 0) << "of " << taken.load() << " values taken, some were not a whole frame's sum";
}

TEST(DeformingBrainTest, NodeForcesSumToTheContactForceAndActWhereItActs) {
  ChannelHub hub;
  TetraBrain brain;
  cubeBrain(brain, 22);
  brain.connectChannels(hub);
  ChannelReader<NodeForces> reader = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
  const std::vector<ShellPoint> shell = sphereShell(2.5, 266);
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  brain.prepare(RunPlan{});
  const Pose pose{Vec3(13.1, -4.2, 100 + 2.5 - 0.8), Quat::Identity()};
  const ShellContact contact = brain.collide(pose, shell, false, memory_brain_shell);
  ASSERT_GT(contact.points, 10);
  const Vec3 force(0.05, -0.02, -0.3);  // N, on the brain
  shapes::respondAlone(brain, pressing(1.25, force, contact.sites));
  ASSERT_TRUE(reader.fetch()) << "a reader is there: the node forces are published";
  const NodeForces& forces = reader.read();
  EXPECT_DOUBLE_EQ(forces.t, 1.25);
  ASSERT_GE(forces.forces.size(), 3u);
  Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
  for (size_t i = 0; i < forces.forces.size(); ++i) {
    sum += forces.forces[i].force;
    moment += brain.node(forces.forces[i].node).cross(forces.forces[i].force);
  }
  EXPECT_NEAR((sum - force).norm(), 0.0, 1e-12);
  // Where it acts: the colliding points averaged by their depth below the top face.
  Vec3 centre = Vec3::Zero();
  double depths = 0;
  for (const ShellPoint& s : shell) {
    const Vec3 p = pose.position + s.position;
    if (shapes::native(brain).locate(p) < 0) continue;
    centre += (100 - p.z()) * p;
    depths += 100 - p.z();
  }
  centre /= depths;
  EXPECT_NEAR((moment - centre.cross(force)).norm(), 0.0, 1e-9);
  // Each node once.
  for (size_t i = 0; i < forces.forces.size(); ++i)
    for (size_t j = i + 1; j < forces.forces.size(); ++j) EXPECT_NE(forces.forces[i].node, forces.forces[j].node);
}

class PublishingNodeForces : public ::testing::TestWithParam<double> {};

// Also with the forces shared among the nodes around (forceSpread, mm).
TEST_P(PublishingNodeForces, EveryFrameAllocatesNothing) {
  ChannelHub hub;
  TetraBrain brain;
  if (GetParam() > 0) {
    ASSERT_TRUE(brain.findField("forceSpread")->assign(std::to_string(GetParam()), {}, {}) == std::nullopt);
  }
  cubeBrain(brain, 22);
  brain.connectChannels(hub);
  ChannelReader<NodeForces> reader = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
  const std::vector<ShellPoint> shell = sphereShell(8.0, 466);  // an 8 mm tool over 9 mm cells
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  brain.prepare(RunPlan{});
  size_t published = 0, largest = 0;
  test::startCountingAllocations();
  // Contacts from none to deep and back: the number of nodes touched varies.
  for (int frame = 0; frame < 400; ++frame) {
    const double press = 6.0 * std::sin(frame * 0.05);
    const Pose pose{Vec3(13.1 + 0.01 * frame, -4.2, 100 + 8.0 - press), Quat::Identity()};
    const ShellContact contact = brain.collide(pose, shell, false, memory_brain_shell);
    if (contact.points > 0)
      shapes::respondAlone(brain, pressing(frame * 1e-3, Vec3(0, 0, -0.3 * press), contact.sites));
    if (reader.fetch()) {
      ++published;
      largest = std::max(largest, reader.read().forces.size());
    }
  }
  EXPECT_EQ(test::stopCountingAllocations(), 0u);
  EXPECT_GT(published, 100u);
  EXPECT_GT(largest, 20u) << "deep contacts touch many nodes";
}
INSTANTIATE_TEST_SUITE_P(DeformingBrainTest, PublishingNodeForces, ::testing::Values(0.0, 20.0));

std::string deformingScene(const std::string& brain, const std::string& deformation) {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=13" )" +
         brain + R"(/>
    )" + deformation +
         R"(
  </Node>
  )" + test::brainProbeNode(R"(path="pokes" center="5 5 0" standoff="5" depth="2")") +
         R"(
</Node>)";
}

TEST(DeformingBrainTest, ASecondDeformationOfOneMeshIsRefusedAtItsLink) {
  Diagnostics d;
  const auto simulation =
      test::loadScene(deformingScene("", R"(<ScriptedDeformation name="a" mesh="@brain" rate="1000"/>
    <ScriptedDeformation name="b" mesh="@brain" rate="1000"/>)"),
                      d);
  EXPECT_FALSE(simulation);
  const std::string text = test::messages(d);
  EXPECT_NE(text.find("inline.xml:7:41:"), std::string::npos) << text;
  EXPECT_NE(text.find("already deforms"), std::string::npos) << text;
}

TEST(DeformingBrainTest, ADeformationRefusesAZeroDirectionAndFieldsItsShapeIgnores) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(
      deformingScene("", R"(<ScriptedDeformation name="a" mesh="@brain" direction="0 0 0" radius="3" rate="1000"/>)"),
      d));
  const std::string text = test::messages(d);
  EXPECT_NE(text.find("direction must be a non-zero vector"), std::string::npos) << text;
  EXPECT_NE(text.find("has no effect with shape=\"wave\""), std::string::npos) << text;
}

TEST(DeformingBrainTest, BoxRefreshWithTheGridSearchIsAnError) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(deformingScene(R"(boxRefresh="moved")", ""), d));
  EXPECT_NE(test::messages(d).find("boxRefresh applies to the thesis's searches"), std::string::npos)
      << test::messages(d);
}

TEST(DeformingBrainTest, ThesisRefreshOfMovedBoxesFindsWhatRefreshingAllFinds) {
  // A bump under the tool moves a few nodes; refreshing only their tets' boxes
  // must give the same contacts as refreshing every box, for far fewer boxes.
  std::vector<HapticFrame> frames[2];
  double refreshed[2] = {0, 0};
  int k = 0;
  for (const char* refresh : {"all", "moved"}) {
    Diagnostics d;
    SimulationOptions options;
    options.duration = 1.5;
    auto simulation = test::loadScene(
        deformingScene(std::string(R"(search="previous-contact" boxRefresh=")") + refresh + "\"",
                       R"(<ScriptedDeformation name="bump" mesh="@brain" shape="bump" center="5 5 100" radius="25"
                            amplitude="1.5" period="0.4" rate="1000"/>)"),
        d, options);
    ASSERT_TRUE(simulation) << test::messages(d);
    simulation->run();
    const HapticFrameLog& log = simulation->hapticLog();
    for (size_t i = 0; i < log.size(); ++i) frames[k].push_back(log[i]);
    refreshed[k] = test::componentCounter(*simulation, "TetraBrain", "refreshed_boxes");
    EXPECT_GT(test::componentCounter(*simulation, "TetraBrain", "contact_frames"), 200.0);
    ++k;
  }
  ASSERT_EQ(frames[0].size(), frames[1].size());
  for (size_t i = 0; i < frames[0].size(); ++i) {
    ASSERT_EQ(frames[0][i].force, frames[1][i].force) << "frame " << i;
  }
  EXPECT_LT(refreshed[1] * 20, refreshed[0]) << "only the bump's tets are refreshed";
}

TEST(DeformingBrainTest, PokingAPulsatingBrainStaysStable) {
  // Every node moves every frame (a 1 mm wave, 1 Hz) while the tool pokes.
  Diagnostics d;
  SimulationOptions options;
  options.duration = 4.0;
  auto simulation = test::loadScene(
      deformingScene("", R"(<ScriptedDeformation name="wave" mesh="@brain" amplitude="1" center="5 5 100"
                            rate="1000"/>)"),
      d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  const HapticStats s = simulation->hapticLog().stats();
  EXPECT_EQ(s.nanFrames, 0u);
  EXPECT_EQ(s.proxyInsideFrames, 0u);
  EXPECT_GT(s.contactFrames, 1000u);
  EXPECT_LE(s.forceStepMax, 0.8) << "N per frame, the thesis's largest peak";
  EXPECT_EQ(test::componentCounter(*simulation, "TetraBrain", "deformation_frames"), 4000.0);
  EXPECT_EQ(test::componentCounter(*simulation, "TetraBrain", "frames_beyond_margin"), 0.0);
}

}  // namespace
}  // namespace trephine::tetra
