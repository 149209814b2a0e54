// grip's hand interaction (thesis 3.5-3.7, 3.9): tracked hands move bodies only through
// friction forces applied with World::addForceAtPosition. Hands are not bodies: the engine's
// contact solver never sees them.
//
//   Interaction ix(world);                       // or InteractionDef{...}
//   HandId h = ix.addHand(HandDef{});
//   every frame:  ix.setHandPose(h, pose);  ix.update(world, dt);  world.step(dt);
//
// See docs/interaction.md for the force law, the implicit spring that keeps it stable, the
// contact rules and the figures.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "dynamics/world.hpp"
#include "interaction/force_law.hpp"
#include "interaction/hand.hpp"
#include "interaction/scripted.hpp"
#include "interaction/tracking.hpp"

namespace grip {

struct HandTag;
using HandId = Id<HandTag>;

enum class InteractionMethod : uint8_t {
  Friction,   // the thesis's Coulomb-friction method (3.5)
  Kinematic,  // the baseline of 3.9 (Kim & Park 2015): a firm grip attaches the body
};

// How a contact point is put on the surface: the thesis's ray toward the centre of the touched
// sub-shape, or the closest surface point (exact with a signed-distance field). Auto: closest
// point where the body's shape has an SDF, ray cast otherwise. The same choice projects
// slipping points back onto the surface (3.5.3).
enum class ContactPointMethod : uint8_t { Auto, RayCast, ClosestPoint };

// Explicit springs are here only to show that they diverge (see the stability tests).
enum class SpringIntegration : uint8_t { Implicit, Explicit };

struct InteractionDef {
  InteractionMethod method = InteractionMethod::Friction;
  SlipLaw slipLaw = SlipLaw::KineticCoulomb;
  ContactPointMethod contactPoint = ContactPointMethod::Auto;
  SpringIntegration integration = SpringIntegration::Implicit;
  // Let the implicit spring know about the World's own contact forces on a body (measured over
  // the last step), so that a body resting on a floor gets exactly gamma * depth. Off: gravity
  // and host forces only.
  bool observedExternalForce = true;
  double gamma = 400.0;            // N/m per bone contact (split over the patch samples)
  double contactOffset = 0.005;    // m: a contact begins within this distance of a body
  double releaseMargin = 0.005;    // m: ...and ends beyond contactOffset + releaseMargin
  int patchSamples = 9;            // 1, 5 or 9 points per contact patch (3.5.4)
  double patchRadius = 0.004;      // m, finger patches
  double widePatchRadius = 0.008;  // m, thumb patches
  double palmPatchRadius = 0.015;  // m, the palm: wide enough to carry an object lying on it
  SkinFriction skin = skinFriction(SkinContactMaterial::Average);
  bool surfaceUpdates = true;  // slide slipping contact points along the surface (3.5.3)
  // A bone that first meets a body already deeper than this stays passive until it has come
  // out to this depth: tracking that resumes inside an object must not launch it.
  double resumeDepth = 0.01;
  double trackingGrace = 0.1;       // s: a dropout shorter than this keeps the grasp
  double teleportDistance = 0.15;   // m: a bone jumping farther in one frame releases the hand
  double kinematicGripForce = 1.0;  // N: total normal grip that attaches (baseline only)
  // The bodies the hands touch, by kind (CollisionFilter::category); the default touches all.
  QueryFilter touchable = {};
};

// Per-body settings; unset fields use the InteractionDef's.
struct BodyInteractionDef {
  double gamma = 0.0;            // > 0 overrides InteractionDef.gamma
  bool autoGamma = false;        // eq. 3.11 from the body's mass and bounding sphere
  double staticFriction = 0.0;   // > 0 overrides the skin friction
  double dynamicFriction = 0.0;  // > 0 overrides the skin friction
};

// A hand-body contact: begins when a bone comes within the contact offset of a body, ends when
// it leaves contactOffset + releaseMargin, the hand is released (tracking lost beyond the grace
// period, a teleporting frame, removeHand) or the body is destroyed.
struct HandContactEvent {
  HandId hand;
  int bone = 0;
  BodyId body;
  Vec3 point = Vec3::Zero();    // world, on the body surface
  Vec3 normal = Vec3::UnitY();  // world, outward from the body
};

// The state of one contact after the last update.
struct HandContactInfo {
  HandId hand;
  int bone = 0;
  BodyId body;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();
  bool pressing = false;      // anchored and compressive: it transmits force
  bool slipping = false;      // some patch sample outside the static cone
  Vec3 force = Vec3::Zero();  // total applied on the body (sum over the patch)
};

struct InteractionStats {
  int trackedHands = 0;
  int contacts = 0;
  int pressingContacts = 0;
  int samples = 0;  // patch samples that applied force
  int slippingSamples = 0;
  int touchedBodies = 0;
  int attachedBodies = 0;     // kinematic baseline
  int droppedFrames = 0;      // frames rejected since creation (non-finite)
  double springEnergy = 0.0;  // J, sum of k |p - C|^2 / 2 over pressing samples (diagnostics)
};

enum class FrameStatus : uint8_t { Accepted, NotTracked, RejectedNonFinite, Teleported };

class Interaction {
 public:
  explicit Interaction(const InteractionDef& def = InteractionDef{});
  ~Interaction();
  Interaction(const Interaction&) = delete;
  Interaction& operator=(const Interaction&) = delete;

  HandId addHand(const HandDef& def);
  void removeHand(HandId id);  // ends its contacts (events at the next update)
  bool isValid(HandId id) const;
  std::vector<HandId> hands() const;

  // One tracking frame for a hand, to be used by the next update. Tracking glitches are not
  // errors: an untracked pose counts as a dropout, a non-finite pose is rejected (dropout), a
  // pose whose bones jumped farther than teleportDistance releases the hand's contacts and is
  // accepted. Only an unknown hand id throws.
  FrameStatus setHandPose(HandId id, const HandPose& pose);

  void setBodyOverrides(BodyId body, const BodyInteractionDef& def);
  void clearBodyOverrides(BodyId body);

  // Finds contacts and applies this step's hand forces to `world` (addForceAtPosition only).
  // Call once per world step, before World::step, with the same dt.
  void update(World& world, double dt);
  // update(world, dt) then world.step(dt).
  void step(World& world, double dt);

  // Outputs of the last update.
  const std::vector<HandContactEvent>& contactBeginEvents() const;
  const std::vector<HandContactEvent>& contactEndEvents() const;
  std::vector<HandContactInfo> contacts() const;
  // The pose tracking gave (the last accepted frame) and the pose to draw (3.6): bones pressing
  // on a body keep their pose relative to it from the moment of contact; free bones follow
  // tracking.
  const HandPose& trackedPose(HandId id) const;
  const HandPose& visualPose(HandId id) const;
  const HandDef& handDef(HandId id) const;
  // Kinematic baseline: whether the body is attached to a hand.
  bool isAttached(BodyId body) const;
  // Sum of the forces applied to a body by the last update (all hands).
  Vec3 appliedForce(BodyId body) const;
  const InteractionStats& stats() const;
  const InteractionDef& def() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace grip
