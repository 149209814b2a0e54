// The placement evaluation (thesis 5.2): a scripted user moves a cube across a chessboard.
//
// The user (Controller) sees the cube through the same noise as its hand is tracked, and works
// in actions, each a short keyframed motion of the fingertips planned from what it saw:
//   grasp-and-place: pinch the cube between thumb and index, lift 2 cm, carry, set down, open;
//   push / pull:     one fingertip against the near (push) or far (pull) face, moved so that the
//                    cube should end on the target along that face's axis.
// The first action is a grasp-and-place; then, while the cube looks farther than `tolerance`
// from the target and time is left, it corrects: a push or pull for small errors, a new
// grasp-and-place for large ones or once a push did not move the cube (the kinematic baseline
// only moves what it grips, so pushes do nothing there). Both methods get the same trials, the
// same noise streams and this same controller.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"
#include "scene/placement.hpp"
#include "scene/scene.hpp"

namespace grip::scene {

namespace {

constexpr double kSquare = 0.05;  // chessboard square (m), 8 x 8 centred on the origin
constexpr double kHalf = 0.02;    // cube half width (4 cm cube)
constexpr double kMass = 0.1;     // kg
constexpr double kBoardMuS = 0.5, kBoardMuD = 0.4;
constexpr double kLift = 0.02;        // m, carry height above the board
constexpr double kCarrySpeed = 0.15;  // m/s
constexpr double kPushSpeed = 0.05;   // m/s
constexpr double kSettle = 0.3;       // s waited before looking again
constexpr int kMaxActions = 12;

Vec3 squareCentre(int i, int j) {
  return Vec3((i - 3.5) * kSquare, 0.0, (j - 3.5) * kSquare);
}

// A keyframed motion: bone poses at times relative to its start (samplePoses in between).
using Motion = PoseKeys;

class Trial {
 public:
  Trial(InteractionMethod method, const PlacementDef& def, uint64_t noiseSeed, const Vec3& start)
      : def_(def), dt_(1.0 / def.hz), ix_(makeInteraction(method)), rng_(noiseSeed) {
    scenarios::addFloor(world_, kBoardMuS, kBoardMuD);
    cube_ = scenarios::addBox(world_, Vec3::Constant(kHalf), kMass, start + Vec3(0, kHalf, 0),
                              Quat::Identity(), kBoardMuS, kBoardMuD);
    hand_ = ix_.addHand(hd_);
    rest_ = scenarios::parkedHand(hd_);
  }

  double time() const { return t_; }
  Vec3 cubeCentre() const { return world_.centerOfMass(cube_); }

  // What the user sees: the cube's centre and its yaw, through the tracking noise.
  void look(Vec3& centre, double& yaw) {
    centre = cubeCentre() + jitter();
    const Vec3 ax = world_.pose(cube_).q * Vec3::UnitX();
    yaw = std::atan2(-ax.z(), ax.x());
  }

  void play(const Motion& m) {
    const double t0 = t_;
    const double end = t0 + m.back().first;
    while (t_ < end - 0.5 * dt_) frame(samplePoses(m, t_ - t0));
  }
  void wait(double seconds) {
    const double end = t_ + seconds;
    while (t_ < end - 0.5 * dt_) frame(rest_);
  }

  // ---- motions ----------------------------------------------------------------------------
  // Thumb and index on the cube's +-x faces (yaw-rotated), sunk `depth`, palm parked 10 m above
  // (it moves with the fingers, so the kinematic baseline carries the cube along).
  HandPose pinch(const Vec3& centre, double yaw, double depth) const {
    const Mat3 r = Eigen::AngleAxisd(yaw, Vec3::UnitY()).toRotationMatrix();
    const Vec3 ex = r * Vec3::UnitX(), ez = r * Vec3::UnitZ();
    HandPose p = scenarios::parkedHand(hd_, centre + Vec3(0, 10, 0));
    scenarios::pressBone(p, hd_, boneIndex(Finger::Thumb, 2), centre - kHalf * ex, -ex, ez, depth);
    scenarios::pressBone(p, hd_, boneIndex(Finger::Index, 2), centre + kHalf * ex, ex, ez, depth);
    return p;
  }
  // The index fingertip against a face with outward normal -d through facePoint, sunk `depth`,
  // its capsule lying flat across the face.
  HandPose fingertip(const Vec3& facePoint, const Vec3& d, double depth) const {
    HandPose p = scenarios::parkedHand(hd_, facePoint + Vec3(0, 10, 0));
    scenarios::pressBone(p, hd_, boneIndex(Finger::Index, 2), facePoint, -d, d.cross(Vec3::UnitY()),
                         depth);
    return p;
  }

 private:
  static InteractionDef makeInteraction(InteractionMethod method) {
    InteractionDef d;
    d.method = method;
    return d;
  }

  Vec3 jitter() {
    const double s = def_.noise / std::sqrt(3.0);
    return Vec3(s * gauss_(rng_), s * gauss_(rng_), s * gauss_(rng_));
  }

  void frame(HandPose pose) {
    for (Transform& b : pose.bones) b.p += jitter();
    pose.tracked = true;
    ix_.setHandPose(hand_, pose);
    ix_.update(world_, dt_);
    world_.step(dt_);
    t_ += dt_;
  }

  const PlacementDef& def_;
  double dt_;
  World world_;
  Interaction ix_;
  HandDef hd_;
  BodyId cube_;
  HandId hand_;
  HandPose rest_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gauss_{0.0, 1.0};
  double t_ = 0.0;
};

// The hold depth of the pinch: 2.5 times the two-finger threshold 2 mu_s gamma depth = m g.
double pinchDepth() {
  const InteractionDef d;
  return 2.5 * kMass * 9.81 / (2.0 * d.skin.staticFriction * d.gamma);
}

void graspAndPlace(Trial& tr, const Vec3& seen, double yaw, const Vec3& target) {
  const double depth = pinchDepth();
  const Vec3 from = Vec3(seen.x(), kHalf, seen.z());
  // Set down 1 mm low so that the board, not the grip, carries the cube before it opens.
  const Vec3 to = Vec3(target.x(), kHalf - 0.001, target.z()), up(0, kLift, 0);
  const double carry = std::max(0.2, (to - from).norm() / kCarrySpeed);
  Motion m;
  double t = 0.0;
  m.emplace_back(t, tr.pinch(from, yaw, -0.01));
  m.emplace_back(t += 0.3, tr.pinch(from, yaw, depth));
  m.emplace_back(t += 0.2, tr.pinch(from, yaw, depth));
  m.emplace_back(t += 0.3, tr.pinch(from + up, yaw, depth));
  m.emplace_back(t += carry, tr.pinch(to + up, yaw, depth));
  m.emplace_back(t += 0.4, tr.pinch(to, yaw, depth));
  m.emplace_back(t += 0.1, tr.pinch(to, yaw, depth));
  m.emplace_back(t += 0.3, tr.pinch(to, yaw, -0.01));
  tr.play(m);
}

// Pushes (or pulls) the cube by `s` (> 0) along the unit board direction d, a face axis.
void push(Trial& tr, const Vec3& seen, const Vec3& d, double s) {
  constexpr double kDepth = 0.004;
  // At rest the fingertip still presses by mu_s m g / gamma (static friction holds the cube
  // against it); move the finger that much farther.
  const InteractionDef id;
  const double residual = kBoardMuS * kMass * 9.81 / id.gamma;
  const Vec3 face = Vec3(seen.x(), kHalf, seen.z()) - kHalf * d;
  const Vec3 end = face + (s + residual - kDepth) * d;
  Motion m;
  double t = 0.0;
  m.emplace_back(t, tr.fingertip(face, d, -0.01));
  m.emplace_back(t += 0.25, tr.fingertip(face, d, kDepth));
  m.emplace_back(t += std::max(0.1, s / kPushSpeed), tr.fingertip(end, d, kDepth));
  m.emplace_back(t += 0.1, tr.fingertip(end, d, kDepth));
  m.emplace_back(t += 0.2, tr.fingertip(end, d, -0.015));
  tr.play(m);
}

PlacementTrial runTrial(InteractionMethod method, const PlacementDef& def, uint64_t noiseSeed,
                        const Vec3& start, const Vec3& target) {
  Trial tr(method, def, noiseSeed, start);
  PlacementTrial out;
  out.start = start;
  out.target = target;
  tr.wait(0.2);  // the cube settles on the board
  bool pushesWork = true;
  for (int action = 0; action < kMaxActions && tr.time() < def.timeLimit; ++action) {
    Vec3 seen;
    double yaw = 0.0;
    tr.look(seen, yaw);
    Vec3 e = target - seen;
    e.y() = 0.0;
    if (action > 0 && e.norm() < def.tolerance) break;
    // The face axis most along the error.
    const Mat3 r = Eigen::AngleAxisd(yaw, Vec3::UnitY()).toRotationMatrix();
    const Vec3 ex = r * Vec3::UnitX(), ez = r * Vec3::UnitZ();
    const Vec3 axis = std::abs(e.dot(ex)) >= std::abs(e.dot(ez)) ? ex : ez;
    const double along = e.dot(axis);
    const bool small = std::abs(along) < 0.02 && (e - along * axis).norm() < 0.01;
    if (action == 0 || !small || !pushesWork) {
      graspAndPlace(tr, seen, yaw, target);
      ++out.grasps;
    } else {
      const Vec3 d = along > 0.0 ? axis : Vec3(-axis);
      const Vec3 before = seen;
      push(tr, seen, d, std::abs(along));
      // The user is at +z looking along -z: moving the cube toward it is a pull.
      (d.z() > 0.5 ? out.pulls : out.pushes) += 1;
      tr.wait(kSettle);
      Vec3 after;
      tr.look(after, yaw);
      if ((after - before).dot(d) < 0.3 * std::abs(along)) pushesWork = false;
      continue;
    }
    tr.wait(kSettle);
  }
  out.time = tr.time();
  Vec3 err = tr.cubeCentre() - target;
  err.y() = 0.0;
  out.error = err.norm();
  return out;
}

std::string pm(const Summary& s, double scale, const char* f) {
  char b[96];
  std::snprintf(b, sizeof b, f, scale * s.mean, scale * s.sd, scale * s.median);
  return b;
}

}  // namespace

Summary summarize(std::vector<double> v) {
  Summary s;
  if (v.empty()) return s;
  double sum = 0.0;
  for (double x : v) sum += x;
  s.mean = sum / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return s;
}

std::vector<PlacementMethod> evaluatePlacement(const PlacementDef& def) {
  if (def.trials <= 0)
    throw Error("trials", "must be positive (got " + std::to_string(def.trials) + ")");
  if (def.trials > 100000) throw Error("trials", "must be at most 100000");
  if (!(def.noise >= 0.0) || !std::isfinite(def.noise) || def.noise > 0.05)
    throw Error("noise", "must be between 0 and 0.05 m");
  if (!(def.hz >= 10.0 && def.hz <= 10000.0)) throw Error("hz", "must be between 10 and 10000");
  if (!(def.timeLimit > 0.0 && def.timeLimit <= 3600.0))
    throw Error("timeLimit", "must be in (0, 3600] s");
  if (!(def.tolerance > 0.0 && def.tolerance < 0.05))
    throw Error("tolerance", "must be in (0, 0.05) m");

  // Start and target squares from the seed, distinct; each trial's noise seed is shared by the
  // two methods.
  std::mt19937_64 layout(def.seed * 0x9E3779B97F4A7C15ull + 0x5EEDull);
  std::uniform_int_distribution<int> square(0, 7);
  struct Layout {
    Vec3 start, target;
    uint64_t noiseSeed;
  };
  std::vector<Layout> trials;
  for (int k = 0; k < def.trials; ++k) {
    int a, b, c, d;
    do {
      a = square(layout), b = square(layout), c = square(layout), d = square(layout);
    } while (a == c && b == d);
    trials.push_back({squareCentre(a, b), squareCentre(c, d), layout()});
  }
  std::vector<PlacementMethod> out;
  for (const auto& [method, name] : {std::pair{InteractionMethod::Friction, "coulomb"},
                                     std::pair{InteractionMethod::Kinematic, "kinematic"}}) {
    PlacementMethod r;
    r.method = name;
    std::vector<double> errors, times;
    for (const Layout& l : trials) {
      r.trials.push_back(runTrial(method, def, l.noiseSeed, l.start, l.target));
      errors.push_back(r.trials.back().error);
      times.push_back(r.trials.back().time);
    }
    r.error = summarize(errors);
    r.time = summarize(times);
    out.push_back(std::move(r));
  }
  return out;
}

std::string placementTable(const PlacementDef& def, const std::vector<PlacementMethod>& results) {
  char head[256];
  std::snprintf(head, sizeof head,
                "placement (thesis 5.2): %d trials, seed %llu, tracking noise %.2g mm rms, %g Hz\n",
                def.trials, static_cast<unsigned long long>(def.seed), 1000.0 * def.noise, def.hz);
  std::string s = head;
  s += "method      positioning error / mm   time per trial / s   grasps  pushes  pulls\n";
  for (const PlacementMethod& r : results) {
    int g = 0, p = 0, q = 0;
    for (const PlacementTrial& t : r.trials) g += t.grasps, p += t.pushes, q += t.pulls;
    char line[256];
    std::snprintf(line, sizeof line, "%-11s %-24s %-20s %6d  %6d  %5d\n", r.method.c_str(),
                  pm(r.error, 1000.0, "%.1f ± %.1f / %.1f").c_str(),
                  pm(r.time, 1.0, "%.1f ± %.1f / %.1f").c_str(), g, p, q);
    s += line;
  }
  return s;
}

}  // namespace grip::scene
