// Running a scene: build the world and hands, step to the duration, stream the recording, collect
// metrics and evaluate the checks.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <tuple>

#include "interaction/scenarios.hpp"
#include "scene/scene.hpp"

namespace grip::scene {

using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// ---- hands ------------------------------------------------------------------------------------

// Gives the tracked pose of one scripted hand at time t. Hands keyed by palm poses only use the
// interaction module's ScriptedHand (joint-space interpolation, noise, tracking loss); hands with
// pinch/press keys interpolate each bone between the keyframes' poses.
class HandScript {
 public:
  HandScript(const HandSpec& spec, uint64_t seed) : spec_(spec) {
    if (!spec.tracked.empty()) return;  // a recorded tracking file
    const bool palmOnly = std::all_of(spec.keys.begin(), spec.keys.end(), [](const KeySpec& k) {
      return k.palm && !k.pinch && k.press.empty() && k.tracked;
    });
    if (palmOnly) {
      ScriptedHandDef d;
      d.hand = spec.def;
      for (const KeySpec& k : spec.keys) d.keys.push_back({k.time, *k.palm, k.pose, std::nullopt});
      d.positionNoise = spec.positionNoise;
      d.rotationNoise = spec.rotationNoise;
      d.seed = seed;
      d.trackingLoss = spec.trackingLoss;
      scripted_ = std::make_unique<ScriptedHand>(std::move(d));
      return;
    }
    for (const KeySpec& k : spec.keys) poses_.emplace_back(k.time, keyPose(k));
  }

  HandPose sample(double t) const {
    if (scripted_) return scripted_->sample(t);
    // A recorded file's frames are real positions: never treated as jumps.
    HandPose p =
        spec_.tracked.empty() ? samplePoses(poses_, t) : samplePoses(spec_.tracked, t, kInfinity);
    for (const auto& [a, b] : spec_.trackingLoss)
      if (t >= a && t <= b) p.tracked = false;
    return p;
  }

 private:
  HandPose keyPose(const KeySpec& k) const {
    const HandDef& d = spec_.def;
    HandPose p;
    if (k.palm) {
      p = poseHand(d, *k.palm, handShape(k.pose));
    } else {
      Vec3 anchor = Vec3::Zero();
      if (k.pinch) {
        anchor = k.pinch->center;
      } else {
        for (const BonePress& b : k.press) anchor += b.point / static_cast<double>(k.press.size());
      }
      p = scenarios::parkedHand(d, k.park ? *k.park : anchor + Vec3(0.0, 10.0, 0.0));
      if (k.pinch) {
        const HandPose pinch =
            scenarios::pinchCube(d, k.pinch->center, k.pinch->halfWidth, k.pinch->depth);
        for (Finger f : {Finger::Thumb, Finger::Index})
          p.bones[boneIndex(f, 2)] = pinch.bones[boneIndex(f, 2)];
      }
    }
    for (const BonePress& b : k.press)
      scenarios::pressBone(p, d, b.bone, b.point, b.normal, b.axis, b.depth);
    p.tracked = k.tracked;
    return p;
  }

  const HandSpec& spec_;
  std::unique_ptr<ScriptedHand> scripted_;
  PoseKeys poses_;
};

// ---- recording (JSON Lines, see docs/scenes.md) -----------------------------------------------

class LineWriter {
 public:
  void num(double x) {
    if (!std::isfinite(x)) {
      buf_ += "null";
      return;
    }
    char tmp[32];
    const auto r = std::to_chars(tmp, tmp + sizeof tmp, x);
    buf_.append(tmp, r.ptr);
  }
  void vec(const Vec3& v) {
    buf_ += '[';
    num(v.x()), buf_ += ',', num(v.y()), buf_ += ',', num(v.z());
    buf_ += ']';
  }
  // [px, py, pz, qw, qx, qy, qz]
  void pose(const Transform& t) {
    buf_ += '[';
    num(t.p.x()), buf_ += ',', num(t.p.y()), buf_ += ',', num(t.p.z()), buf_ += ',';
    num(t.q.w()), buf_ += ',', num(t.q.x()), buf_ += ',', num(t.q.y()), buf_ += ',', num(t.q.z());
    buf_ += ']';
  }
  std::string& raw() { return buf_; }

 private:
  std::string buf_;
};

class Recording {
 public:
  Recording(const std::filesystem::path& dir, const std::string& file)
      : final_(dir / file), temp_(dir / (file + ".partial")) {
    f_ = std::fopen(temp_.c_str(), "wb");
    if (!f_)
      throw Error(dir.string(), std::string("cannot write the recording: ") + std::strerror(errno));
  }
  ~Recording() {
    if (f_) {  // not committed: an error happened; leave nothing that looks complete
      std::fclose(f_);
      std::error_code ec;
      std::filesystem::remove(temp_, ec);
    }
  }
  void write(const std::string& line) {
    if (std::fwrite(line.data(), 1, line.size(), f_) != line.size() ||
        std::fputc('\n', f_) == EOF) {
      throw Error(temp_.string(), std::string("write failed: ") + std::strerror(errno));
    }
  }
  void commit() {
    const bool ok = std::fflush(f_) == 0 && !std::ferror(f_);
    const int err = errno;
    std::fclose(f_);
    f_ = nullptr;
    std::error_code ec;
    if (!ok) {
      std::filesystem::remove(temp_, ec);
      throw Error(temp_.string(), std::string("write failed: ") + std::strerror(err));
    }
    std::filesystem::rename(temp_, final_, ec);
    if (ec) {
      std::error_code removeError;  // the rename's error is the one to report
      std::filesystem::remove(temp_, removeError);
      throw Error(final_.string(), "cannot rename the finished recording: " + ec.message());
    }
  }
  std::string path() const { return final_.string(); }

 private:
  std::filesystem::path final_, temp_;
  std::FILE* f_ = nullptr;
};

json poseJson(const Transform& t) {
  return {{"position", {t.p.x(), t.p.y(), t.p.z()}},
          {"orientation", {t.q.w(), t.q.x(), t.q.y(), t.q.z()}}};
}
json vecJson(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

json shapeJson(const Shape& s) {
  switch (s.type()) {
    case ShapeType::Box:
      return {{"type", "box"}, {"halfExtents", vecJson(s.halfExtents())}, {"rounding", s.radius()}};
    case ShapeType::Sphere:
      return {{"type", "sphere"}, {"radius", s.radius()}};
    case ShapeType::Capsule:
      return {{"type", "capsule"}, {"radius", s.radius()}, {"halfHeight", s.halfHeight()}};
    case ShapeType::Plane:
      return {{"type", "plane"}, {"normal", vecJson(s.planeNormal())}, {"offset", s.planeOffset()}};
    case ShapeType::ConvexHull: {
      json points = json::array(), faces = json::array();
      for (const Vec3& v : s.hull().vertices) points.push_back(vecJson(v));
      for (const ConvexHullData::Face& f : s.hull().faces) faces.push_back(f.vertices);
      return {{"type", "hull"}, {"points", points}, {"faces", faces}, {"rounding", s.radius()}};
    }
    case ShapeType::Compound: {
      json children = json::array();
      for (const CompoundChild& c : s.children()) {
        json child = poseJson(c.local);
        child["shape"] = shapeJson(*c.shape);
        children.push_back(child);
      }
      return {{"type", "compound"}, {"children", children}};
    }
  }
  return {{"type", shapeTypeName(s.type())}};
}

namespace {

// ---- checks -------------------------------------------------------------------------------------

std::string fmt(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

std::string boundText(const std::optional<double>& lo, const std::optional<double>& hi) {
  if (lo && hi) return "in [" + fmt(*lo) + ", " + fmt(*hi) + "]";
  if (lo) return ">= " + fmt(*lo);
  return "<= " + fmt(*hi);
}

bool within(double x, const std::optional<double>& lo, const std::optional<double>& hi) {
  return std::isfinite(x) && (!lo || x >= *lo) && (!hi || x <= *hi);
}

const char* kindName(CheckKind k) {
  switch (k) {
    case CheckKind::Position:
      return "position";
    case CheckKind::Displacement:
      return "displacement";
    case CheckKind::Speed:
      return "speed";
    case CheckKind::LowestHeight:
      return "lowest height";
    case CheckKind::HandContacts:
      return "pressing contacts";
    case CheckKind::Angle:
      return "rotation";
  }
  return "?";
}

// Rotation of q relative to q0 about `axis` (radians, signed), from the swing-twist split.
double twistAngle(const Quat& q0, const Quat& q, const Vec3& axis) {
  const Quat d = q * q0.conjugate();
  const double proj = Vec3(d.x(), d.y(), d.z()).dot(axis);
  double a = 2.0 * std::atan2(proj, d.w());
  if (a > kPi) a -= 2.0 * kPi;
  if (a < -kPi) a += 2.0 * kPi;
  return a;
}

}  // namespace

HandPose samplePoses(const PoseKeys& keys, double t, double jump) {
  size_t i = 0;
  while (i + 1 < keys.size() && keys[i + 1].first <= t) ++i;
  HandPose p = keys[i].second;
  if (i + 1 < keys.size() && t > keys[i].first && p.tracked && keys[i + 1].second.tracked) {
    const double s = (t - keys[i].first) / (keys[i + 1].first - keys[i].first);
    const HandPose& q = keys[i + 1].second;
    for (int b = 0; b < kBonesPerHand; ++b) {
      if ((q.bones[b].p - p.bones[b].p).norm() > jump) continue;
      p.bones[b].p = (1.0 - s) * p.bones[b].p + s * q.bones[b].p;
      p.bones[b].q = p.bones[b].q.slerp(s, q.bones[b].q);
    }
  }
  return p;
}

bool RunResult::allPassed() const {
  return std::all_of(checks.begin(), checks.end(), [](const CheckResult& c) { return c.passed; });
}

RunResult run(const Scene& scene, const RunOptions& options) {
  const auto t0 = Clock::now();
  // parseScene checks this too, but a Scene can be edited after parsing (a shorter duration):
  // a check whose reference time is never reached would read states never taken.
  for (size_t k = 0; k < scene.checks.size(); ++k)
    if (!(scene.checks[k].since < scene.duration))
      throw Error("checks[" + std::to_string(k) + "].since",
                  "must be before the end of the run (duration)");
  World world(scene.world);
  Interaction ix(scene.interaction);
  std::vector<BodyId> ids;
  for (const BodySpec& b : scene.bodies) {
    try {
      ids.push_back(world.createBody(b.def));
    } catch (const Error& e) {
      throw Error("bodies[" + std::to_string(ids.size()) + "]", e.what());
    }
    if (b.interaction) ix.setBodyOverrides(ids.back(), *b.interaction);
  }
  std::vector<JointId> jointIds;
  for (size_t k = 0; k < scene.joints.size(); ++k) {
    JointDef d = scene.joints[k].def;
    d.a = ids[static_cast<size_t>(scene.joints[k].a)];
    d.b = ids[static_cast<size_t>(scene.joints[k].b)];
    try {
      jointIds.push_back(world.createJoint(d));
    } catch (const Error& e) {
      throw Error("joints[" + std::to_string(k) + "]", e.what());
    }
  }
  std::vector<HandId> hands;
  std::vector<HandScript> scripts;
  std::vector<HandShapes> handShapes;
  scripts.reserve(scene.hands.size());
  for (size_t i = 0; i < scene.hands.size(); ++i) {
    const HandSpec& h = scene.hands[i];
    try {
      hands.push_back(ix.addHand(h.def));
      scripts.emplace_back(h, scene.seed * 1000003ull + i);
    } catch (const Error& e) {
      throw Error("hands[" + std::to_string(i) + "]", e.what());
    }
    handShapes.push_back(makeHandShapes(h.def));
  }

  std::unique_ptr<Recording> rec;
  RunResult result;
  const int steps = scene.steps();
  const double dt = scene.dt;
  const int every = std::max(1, options.recordEvery);
  std::filesystem::path dir;
  if (!options.outDir.empty()) {
    dir = options.outDir;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
      throw Error(options.outDir, "cannot create the output directory" +
                                      (ec ? ": " + ec.message() : std::string()));
    }
    rec = std::make_unique<Recording>(dir, "recording.jsonl");
    json header = {
        {"format", "grip-recording"},
        {"version", kRecordingVersion},
        {"scene", scene.name},
        {"dt", dt},
        {"steps", steps},
        {"recordEvery", every},
        {"seed", scene.seed},
        {"method",
         scene.interaction.method == InteractionMethod::Friction ? "coulomb" : "kinematic"}};
    json bodies = json::array();
    for (size_t i = 0; i < ids.size(); ++i) {
      const BodyDef& d = scene.bodies[i].def;
      bodies.push_back({{"name", d.name},
                        {"type", d.type == BodyType::Static      ? "static"
                                 : d.type == BodyType::Kinematic ? "kinematic"
                                                                 : "dynamic"},
                        {"shape", shapeJson(*d.shape)}});
      if (!scene.bodies[i].asset.empty()) bodies.back()["asset"] = scene.bodies[i].asset;
    }
    header["bodies"] = bodies;
    json handsJ = json::array();
    for (size_t i = 0; i < hands.size(); ++i) {
      json bones = json::array();
      for (int b = 0; b < kBonesPerHand; ++b) {
        const Shape& s = *handShapes[i].bones[b];
        bones.push_back({{"name", boneName(b)}, {"shape", shapeJson(s)}});
      }
      handsJ.push_back({{"name", scene.hands[i].def.name},
                        {"side", scene.hands[i].def.side == Handedness::Left ? "left" : "right"},
                        {"bones", bones}});
    }
    header["hands"] = handsJ;
    // Each joint's anchors in its bodies' frames (from the origin, as the frames' poses are):
    // the viewer draws the line between them.
    json jointsJ = json::array();
    for (const JointSpec& j : scene.joints) {
      auto local = [&](int body, const Vec3& anchor) {
        const BodyDef& d = scene.bodies[static_cast<size_t>(body)].def;
        return vecJson(d.orientation.normalized().conjugate() * (anchor - d.position));
      };
      const Vec3& anchorB = j.def.type == JointType::Distance ? j.def.anchorB : j.def.anchor;
      jointsJ.push_back({{"type", kJointTypeNames[static_cast<size_t>(j.def.type)]},
                         {"a", j.a},
                         {"b", j.b},
                         {"anchorA", local(j.a, j.def.anchor)},
                         {"anchorB", local(j.b, anchorB)}});
    }
    header["joints"] = jointsJ;
    rec->write(header.dump());
  }

  // Running measures.
  // Reference states of the displacement and angle checks: at their `since` time.
  std::vector<std::vector<Transform>> reference(scene.checks.size());
  std::vector<std::vector<Vec3>> referenceCom(scene.checks.size());
  auto takeReferences = [&](double t, double stepDt) {
    for (size_t k = 0; k < scene.checks.size(); ++k) {
      if (!reference[k].empty() || scene.checks[k].since > t + 0.5 * stepDt) continue;
      for (BodyId id : ids) {
        reference[k].push_back(world.pose(id));
        referenceCom[k].push_back(world.centerOfMass(id));
      }
    }
  };
  takeReferences(0.0, dt);
  std::vector<Vec3> startCom;
  for (BodyId id : ids) startCom.push_back(world.centerOfMass(id));
  std::vector<double> lowest(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) lowest[i] = startCom[i].y();
  const double energy0 = totalEnergy(world);
  double energyMax = energy0;
  double maxPenTracked = 0.0, maxPenVisual = 0.0;
  long long slipSamples = 0, slipOnsets = 0, contactsBegun = 0;
  json jointBreaks = json::array();  // scene joint index, time, force (N), torque (N m)
  int maxPressing = 0;
  std::map<std::tuple<uint32_t, int, uint32_t>, bool> slipping;
  double tHands = 0.0, tInteraction = 0.0, tStep = 0.0, tRecord = 0.0, tMeasure = 0.0;
  std::vector<Manifold> manifolds;
  LineWriter line;

  auto penetration = [&](size_t h, const HandPose& pose, const HandContactInfo& c) {
    manifolds.clear();
    const int bone = c.bone;
    collide(*handShapes[h].bones[bone], pose.bones[bone], world.shape(c.body), world.pose(c.body),
            0.0, manifolds);
    double deepest = 0.0;
    for (const Manifold& m : manifolds)
      for (int k = 0; k < m.pointCount; ++k) deepest = std::max(deepest, -m.points[k].separation);
    return deepest;
  };

  const auto tLoop = Clock::now();
  for (int step = 0; step < steps; ++step) {
    const double t = step * dt;
    auto a = Clock::now();
    for (size_t h = 0; h < hands.size(); ++h) ix.setHandPose(hands[h], scripts[h].sample(t));
    auto b = Clock::now();
    tHands += seconds(a, b);
    ix.update(world, dt);
    auto c = Clock::now();
    tInteraction += seconds(b, c);
    world.step(dt);
    auto d = Clock::now();
    tStep += seconds(c, d);

    // Measures.
    const std::vector<HandContactInfo> contacts =
        hands.empty() ? std::vector<HandContactInfo>{} : ix.contacts();
    contactsBegun += static_cast<long long>(ix.contactBeginEvents().size());
    for (const JointBreakEvent& e : world.jointBreakEvents()) {
      const auto k = std::find(jointIds.begin(), jointIds.end(), e.joint) - jointIds.begin();
      jointBreaks.push_back({{"joint", k},
                             {"time", (step + 1) * dt},
                             {"force", e.force.norm()},
                             {"torque", e.torque.norm()}});
    }
    slipSamples += ix.stats().slippingSamples;
    maxPressing = std::max(maxPressing, ix.stats().pressingContacts);
    for (const HandContactInfo& ci : contacts) {
      const auto k = std::make_tuple(ci.hand.index, ci.bone, ci.body.index);
      bool& was = slipping[k];
      if (ci.slipping && !was) ++slipOnsets;
      was = ci.slipping;
      const size_t h =
          static_cast<size_t>(std::find(hands.begin(), hands.end(), ci.hand) - hands.begin());
      maxPenTracked = std::max(maxPenTracked, penetration(h, ix.trackedPose(ci.hand), ci));
      maxPenVisual = std::max(maxPenVisual, penetration(h, ix.visualPose(ci.hand), ci));
    }
    for (size_t i = 0; i < ids.size(); ++i)
      lowest[i] = std::min(lowest[i], world.centerOfMass(ids[i]).y());
    takeReferences((step + 1) * dt, dt);
    energyMax = std::max(energyMax, totalEnergy(world));
    auto e = Clock::now();
    tMeasure += seconds(d, e);

    if (rec && (step % every == every - 1 || step + 1 == steps)) {
      std::string& s = line.raw();
      s.clear();
      s += "{\"frame\":" + std::to_string(step + 1) + ",\"t\":";
      line.num((step + 1) * dt);
      s += ",\"bodies\":[";
      for (size_t i = 0; i < ids.size(); ++i) {
        if (i) s += ',';
        line.pose(world.pose(ids[i]));
      }
      s += "],\"hands\":[";
      for (size_t h = 0; h < hands.size(); ++h) {
        if (h) s += ',';
        const HandPose& tp = ix.trackedPose(hands[h]);
        s += tp.tracked ? "{\"tracked\":true,\"bones\":[" : "{\"tracked\":false,\"bones\":[";
        for (int k = 0; k < kBonesPerHand; ++k) {
          if (k) s += ',';
          line.pose(tp.bones[k]);
        }
        s += "],\"visual\":[";
        const HandPose& vp = ix.visualPose(hands[h]);
        for (int k = 0; k < kBonesPerHand; ++k) {
          if (k) s += ',';
          line.pose(vp.bones[k]);
        }
        s += "]}";
      }
      s += "],\"contacts\":[";
      bool first = true;
      for (const HandContactInfo& ci : contacts) {
        if (!first) s += ',';
        first = false;
        const size_t h =
            static_cast<size_t>(std::find(hands.begin(), hands.end(), ci.hand) - hands.begin());
        const size_t bi =
            static_cast<size_t>(std::find(ids.begin(), ids.end(), ci.body) - ids.begin());
        s += "{\"hand\":" + std::to_string(h) + ",\"bone\":" + std::to_string(ci.bone) +
             ",\"body\":" + std::to_string(bi) + ",\"point\":";
        line.vec(ci.point);
        s += ",\"normal\":";
        line.vec(ci.normal);
        s += ",\"force\":";
        line.vec(ci.force);
        s += ",\"state\":\"";
        s += !ci.pressing ? "touch" : ci.slipping ? "slip" : "stick";
        s += "\"}";
      }
      s += "]}";
      rec->write(s);
    }
    tRecord += seconds(e, Clock::now());
    if (options.progress && (step % 64 == 0 || step + 1 == steps))
      options.progress(step + 1, steps);
  }
  const auto tEnd = Clock::now();

  // Checks.
  for (size_t ci = 0; ci < scene.checks.size(); ++ci) {
    const CheckSpec& c = scene.checks[ci];
    CheckResult r;
    r.passed = true;
    std::string what;
    auto bodyName = [&](int i) { return scene.bodies[static_cast<size_t>(i)].def.name; };
    if (c.kind == CheckKind::HandContacts) {
      int n = 0;
      for (const HandContactInfo& info : ix.contacts())
        if (info.pressing && info.hand == hands[static_cast<size_t>(c.hand)]) ++n;
      r.passed = within(n, c.min, c.max);
      what = std::string(kindName(c.kind)) + " of " +
             scene.hands[static_cast<size_t>(c.hand)].def.name;
      r.detail = std::to_string(n) + " (want " + boundText(c.min, c.max) + ")";
    } else {
      what = std::string(kindName(c.kind)) + " of " +
             (c.bodies.size() == 1 ? bodyName(c.bodies[0])
                                   : std::to_string(c.bodies.size()) + " bodies");
      double worst = 0.0;
      std::string worstName;
      bool firstBody = true;
      for (int bi : c.bodies) {
        const BodyId id = ids[static_cast<size_t>(bi)];
        const Vec3 com = world.centerOfMass(id);
        bool ok = true;
        double value = 0.0;
        std::string detail;
        switch (c.kind) {
          case CheckKind::Position: {
            char b[96];
            std::snprintf(b, sizeof b, "(%.4g, %.4g, %.4g)", com.x(), com.y(), com.z());
            detail = b;
            for (int k = 0; k < 3; ++k)
              ok = ok && within(com[k], c.minVec[static_cast<size_t>(k)],
                                c.maxVec[static_cast<size_t>(k)]);
            break;
          }
          case CheckKind::Displacement: {
            const Vec3 dpos = com - referenceCom[ci][static_cast<size_t>(bi)];
            value = c.axis ? dpos.dot(*c.axis) : dpos.norm();
            break;
          }
          case CheckKind::Speed:
            value = world.linearVelocity(id).norm();
            break;
          case CheckKind::LowestHeight:
            value = lowest[static_cast<size_t>(bi)];
            break;
          case CheckKind::Angle:
            value =
                twistAngle(reference[ci][static_cast<size_t>(bi)].q, world.pose(id).q, *c.axis) *
                180.0 / kPi;
            break;
          case CheckKind::HandContacts:
            break;
        }
        if (c.kind != CheckKind::Position) {
          ok = within(value, c.min, c.max);
          detail = fmt(value);
        }
        // Report the body farthest outside (or nearest to leaving) the bounds.
        double badness = -std::numeric_limits<double>::infinity();
        auto worse = [&](double x, const std::optional<double>& lo,
                         const std::optional<double>& hi) {
          if (!std::isfinite(x)) badness = std::numeric_limits<double>::infinity();
          if (lo) badness = std::max(badness, *lo - x);
          if (hi) badness = std::max(badness, x - *hi);
        };
        if (c.kind == CheckKind::Position) {
          for (size_t k = 0; k < 3; ++k) worse(com[static_cast<int>(k)], c.minVec[k], c.maxVec[k]);
        } else {
          worse(value, c.min, c.max);
        }
        if (firstBody || badness > worst) {
          worst = badness;
          worstName = bodyName(bi);
          r.detail = detail;
        }
        firstBody = false;
        if (!ok) r.passed = false;
      }
      if (c.kind == CheckKind::Position) {
        std::string want;
        for (int k = 0; k < 3; ++k) {
          if (c.minVec[static_cast<size_t>(k)] || c.maxVec[static_cast<size_t>(k)]) {
            if (!want.empty()) want += ", ";
            want += "xyz"[k];
            want += ' ';
            want += boundText(c.minVec[static_cast<size_t>(k)], c.maxVec[static_cast<size_t>(k)]);
          }
        }
        r.detail += " (want " + want + ")";
      } else {
        r.detail += " (want " + boundText(c.min, c.max) + ")";
      }
      if (c.bodies.size() > 1) r.detail = worstName + ": " + r.detail;
    }
    r.label = c.label.empty() ? what : c.label;
    result.checks.push_back(r);
  }

  result.stateHash = world.stateHash();
  result.steps = steps;
  result.simulatedTime = steps * dt;
  result.wallSeconds = seconds(t0, Clock::now());

  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(result.stateHash));
  json m;
  m["scene"] = scene.name;
  m["method"] = scene.interaction.method == InteractionMethod::Friction ? "coulomb" : "kinematic";
  m["seed"] = scene.seed;
  m["dt"] = dt;
  m["steps"] = steps;
  m["simulatedTime"] = result.simulatedTime;
  m["wallTime"] = seconds(tLoop, tEnd);
  m["realtimeFactor"] = result.simulatedTime / std::max(1e-9, seconds(tLoop, tEnd));
  m["stateHash"] = hash;
  json finals = json::array();
  for (size_t i = 0; i < ids.size(); ++i) {
    json b = poseJson(world.pose(ids[i]));
    b["name"] = scene.bodies[i].def.name;
    b["linearVelocity"] = vecJson(world.linearVelocity(ids[i]));
    b["angularVelocity"] = vecJson(world.angularVelocity(ids[i]));
    finals.push_back(b);
  }
  m["bodies"] = finals;
  m["hands"] = {{"contactsBegun", contactsBegun},
                {"maxPressingContacts", maxPressing},
                {"slipOnsets", slipOnsets},
                {"slippingSampleSteps", slipSamples},
                {"maxPenetrationTracked", maxPenTracked},
                {"maxPenetrationVisual", maxPenVisual}};
  m["jointBreaks"] = jointBreaks;
  m["energy"] = {{"initial", energy0}, {"final", totalEnergy(world)}, {"max", energyMax}};
  m["timings"] = {{"hands", tHands},   {"interaction", tInteraction},
                  {"step", tStep},     {"measure", tMeasure},
                  {"record", tRecord}, {"total", seconds(t0, tEnd)}};
  json checks = json::array();
  for (const CheckResult& r : result.checks)
    checks.push_back({{"label", r.label}, {"passed", r.passed}, {"detail", r.detail}});
  m["checks"] = checks;
  m["passed"] = result.allPassed();
  result.metrics = m;

  if (rec) {
    rec->write(
        json({{"end", true}, {"frames", (steps + every - 1) / every}, {"stateHash", hash}}).dump());
    rec->commit();
    result.recordingPath = rec->path();
    const std::filesystem::path mp = dir / "metrics.json";
    const std::filesystem::path tmp = dir / "metrics.json.partial";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw Error(tmp.string(), std::string("cannot write: ") + std::strerror(errno));
    const std::string text = m.dump(2) + "\n";
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    const bool closed = std::fclose(f) == 0;
    std::error_code ec;
    if (!ok || !closed) {
      std::filesystem::remove(tmp, ec);
      throw Error(tmp.string(), "write failed");
    }
    std::filesystem::rename(tmp, mp, ec);
    if (ec) throw Error(mp.string(), "cannot rename: " + ec.message());
    result.metricsPath = mp.string();
  }
  return result;
}

}  // namespace grip::scene
