// Joints: fixed, ball, hinge and slider, with limits. Each joint is a few constraint rows
// between two bodies, solved in the soft step as the contacts are (Box2D v3): in each substep's
// biased pass softly toward zero drift (WorldDef::jointHertz), in its relax pass without bias,
// warm started with the impulses of the substep before. The locked rows (up to six) are solved
// together as one block, exactly, so a ball joint's three directions or a weld's six do not
// fight each other as row-by-row passes would; a limit (only pushing) or a motor (within its
// force) is one more row of it. The rows, their coupling and its factor are built each time
// the positions move (frameJoints) and shared by the solves until the next move.
#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamics/detail/world_impl.hpp"

namespace grip {

using detail::Body;
using detail::Joint;
using detail::JointFrame;
using detail::JointPose;
using detail::JointRow;
using detail::JointRows;
using detail::SolverBody;

bool detail::JointRows::finite() const {
  double sum = std::abs(limit.error) + limit.angA.squaredNorm() + limit.angB.squaredNorm();
  for (int k = 0; k < count; ++k)
    sum += std::abs(locked[k].error) + locked[k].angA.squaredNorm() + locked[k].angB.squaredNorm();
  return std::isfinite(sum);
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The rotation vector of q (axis times angle, the angle in [0, pi]).
Vec3 rotationVector(Quat q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (!(s > 0.0)) return Vec3::Zero();
  return (2.0 * std::atan2(s, q.w()) / s) * q.vec();
}

// A body's pose between steps (the public calls; the solve has its own: frameJoints).
JointPose poseOf(const Body& b) {
  JointPose p;
  p.com = b.com, p.q = b.pose.q, p.R = b.pose.q.toRotationMatrix();
  return p;
}

// The joint's rows for its bodies at poses a and b, into `out` (its dwA, dwB left zero).
void jointRows(const Joint& j, const JointPose& pa, const JointPose& pb, JointRows& out) {
  out.count = 0, out.limit = JointRow{}, out.position = 0.0;
  const Quat &qA = pa.q, &qB = pb.q;
  const Vec3 rA = pa.R * j.localA, rB = pb.R * j.localB;
  const Vec3 d = (pb.com + rB) - (pa.com + rA);  // anchor on b from anchor on a
  const bool withAxis = hasAxisPosition(j.type);
  const Vec3 axis = withAxis ? Vec3(pa.R * j.axisA) : Vec3::Zero();
  const bool turning = j.type == JointType::Hinge || j.type == JointType::Slider;
  auto add = [&](const Vec3& lin, const Vec3& angA, const Vec3& angB, double error) {
    out.locked[out.count++] = {lin, angA, angB, error};
  };
  auto lockPoint = [&] {
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = Vec3::Unit(k);
      add(e, rA.cross(e), rB.cross(e), d[k]);
    }
  };
  // No turning: the rotation of b from where a carries its reference pose.
  auto lockTurning = [&] {
    const Vec3 turn = rotationVector(qB * (qA * j.reference).conjugate());
    for (int k = 0; k < 3; ++k) add(Vec3::Zero(), Vec3::Unit(k), Vec3::Unit(k), turn[k]);
  };
  Vec3 t1, t2;
  if (turning) tangentBasis(axis, t1, t2);
  switch (j.type) {
    case JointType::Fixed:
      lockPoint(), lockTurning();
      break;
    case JointType::Ball: {
      lockPoint();
      if (!j.enableLimit) break;
      // The cone: the swing is the angle between the two copies of the axis, turned about
      // their cross product (any normal to a's where they are parallel: far from the cone).
      const Vec3 a = pa.R * j.axisA, b = pb.R * j.axisB, across = a.cross(b);
      const double s = across.norm();
      Vec3 n, unused;
      if (s > 1e-12)
        n = across / s;
      else
        tangentBasis(a, n, unused);
      out.position = std::atan2(s, a.dot(b));
      out.limit = {Vec3::Zero(), n, n, 0.0};
      break;
    }
    case JointType::Hinge: {
      lockPoint();
      // The two axes stay parallel: a x b is the turn off the axis (to first order).
      const Vec3 off = axis.cross(pb.R * j.axisB);
      add(Vec3::Zero(), t1, t1, t1.dot(off));
      add(Vec3::Zero(), t2, t2, t2.dot(off));
      // The angle: the turn of b relative to a since the joint was made, about a's axis.
      Quat turn = qA.conjugate() * qB * j.reference.conjugate();
      if (turn.w() < 0.0) turn.coeffs() = -turn.coeffs();
      out.position = 2.0 * std::atan2(turn.vec().dot(j.axisA), turn.w());
      out.limit = {Vec3::Zero(), axis, axis, 0.0};
      break;
    }
    case JointType::Slider: {
      // Off the rail: a's axis turns with a, so its lever on a reaches to b's anchor.
      add(t1, (rA + d).cross(t1), rB.cross(t1), t1.dot(d));
      add(t2, (rA + d).cross(t2), rB.cross(t2), t2.dot(d));
      lockTurning();
      out.position = axis.dot(d);
      out.limit = {axis, (rA + d).cross(axis), rB.cross(axis), 0.0};
      break;
    }
    case JointType::Distance: {
      // Along the line between the anchors (a's axis where they meet: no line to follow).
      const double length = d.norm();
      const Vec3 u = length > 1e-9 ? Vec3(d / length) : axis;
      out.position = length - j.restLength;
      out.limit = {u, rA.cross(u), rB.cross(u), 0.0};
      // A rod, unless its length may change (a rope's slack, a spring, a winch).
      if (!j.enableLimit && !j.enableSpring && !j.enableMotor)
        add(u, rA.cross(u), rB.cross(u), out.position - j.rodStretch);
      break;
    }
  }
}

// The joint's two bodies as the solve has them; a row's impulse turns them by its dwA and dwB.
struct JointBodies {
  SolverBody& A;
  SolverBody& B;
  double velocity(const JointRow& r) const {
    return r.lin.dot(B.v - A.v) + r.angB.dot(B.w) - r.angA.dot(A.w);
  }
  // A linear impulse p on b (-p on a) and the turns it and the rows' torques give each body.
  void apply(const Vec3& p, const Vec3& dwA, const Vec3& dwB) const {
    const Vec3 dvA = A.invMass * p, dvB = B.invMass * p;
    A.v -= dvA, A.w -= dwA, A.jointV -= dvA, A.jointW -= dwA;
    B.v += dvB, B.w += dwB, B.jointV += dvB, B.jointW += dwB;
  }
  void apply(const JointRow& r, double impulse) const {
    apply(impulse * r.lin, impulse * r.dwA, impulse * r.dwB);
  }
};

// The limit's row for one side: lower (+1) keeps position >= lower, upper (-1) position <= upper.
JointRow limitSide(const JointRows& rows, double bound, double side) {
  JointRow r = rows.limit;
  r.lin *= side, r.angA *= side, r.angB *= side, r.dwA *= side, r.dwB *= side;
  r.error = side * (rows.position - bound);
  return r;
}

// each(row, impulse) for every row of the joint and the accumulated impulse it holds: the locked
// rows, the limit's two sides, the motor, the spring (the warm start, jointForce).
template <class Each>
void forEachHeld(const Joint& j, const JointRows& rows, const Each& each) {
  for (int k = 0; k < rows.count; ++k) each(rows.locked[k], j.impulse[k]);
  if (j.enableLimit) {
    each(limitSide(rows, j.lower, 1.0), j.lowerImpulse);
    each(limitSide(rows, j.upper, -1.0), j.upperImpulse);
  }
  if (j.enableMotor) each(rows.limit, j.motorImpulse);
  if (j.enableSpring) each(rows.limit, j.springImpulse);
}

// The Cholesky factor of K's leading m x m block (m <= 7: a fixed-size 7 x 7 Eigen solve was
// a third of a chain's step); false if the block is not positive definite.
bool factor(JointFrame& f, int m) {
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < i; ++j) {
      double sum = f.K[i][j];
      for (int k = 0; k < j; ++k) sum -= f.L[i][k] * f.L[j][k];
      f.L[i][j] = sum * f.inv[j];
    }
    double sum = f.K[i][i];
    for (int k = 0; k < i; ++k) sum -= f.L[i][k] * f.L[i][k];
    if (!(sum > 0.0)) return false;
    f.inv[i] = 1.0 / std::sqrt(sum);
  }
  return true;
}

// x = K^-1 b for K's leading m x m block, its row n (the axis row) times `sign` (a limit's
// upper side is the axis row negated: its factor row is the axis row's negated, exactly).
void substitute(const JointFrame& f, int n, int m, double sign, const double* b, double* x) {
  auto l = [&](int i, int k) { return i == n ? sign * f.L[i][k] : f.L[i][k]; };
  for (int i = 0; i < m; ++i) {  // L y = b
    double sum = b[i];
    for (int k = 0; k < i; ++k) sum -= l(i, k) * x[k];
    x[i] = sum * f.inv[i];
  }
  for (int i = m - 1; i >= 0; --i) {  // L^T x = y
    double sum = x[i];
    for (int k = i + 1; k < m; ++k) sum -= l(k, i) * x[k];
    x[i] = sum * f.inv[i];
  }
}

// One row of a joint's block: what its velocity is pulled toward (minus the bias), how softly,
// and the bounds of its accumulated impulse; `sign` -1 for the axis row negated (a limit's
// upper side).
struct BlockRow {
  const JointRow* row = nullptr;
  double* accumulated = nullptr;
  double bias = 0.0, massScale = 1.0, impulseScale = 0.0;
  double lo = -kInfinity, hi = kInfinity;
  double sign = 1.0;
};

// The n locked rows (unbounded, of one softness) and the axis row if any solved together:
// K impulse = -(velocity + bias), softened as the contacts are. Where the axis row's total would
// leave its bounds, or its softness is another (a 1 Hz spring beside the 60 Hz locked rows:
// scaling the block's solution row by row threw a door on a spring around at 1500 rad/s), its
// impulse is fixed first and the locked rows solved again with it.
void solveBlock(const JointBodies& jb, const JointFrame& f, const BlockRow* rows, int n,
                const BlockRow* axis) {
  const int m = axis ? n + 1 : n;
  const double sign = axis ? axis->sign : 1.0;
  double rhs[7], x[7], impulse[7];
  for (int r = 0; r < n; ++r) rhs[r] = jb.velocity(*rows[r].row) + rows[r].bias;
  if (axis) rhs[n] = jb.velocity(*axis->row) + axis->bias;
  auto row = [&](int r) -> const BlockRow& { return r < n ? rows[r] : *axis; };
  auto impulsesOf = [&](int count) {
    substitute(f, n, count, sign, rhs, x);
    for (int r = 0; r < count; ++r)
      impulse[r] = -row(r).massScale * x[r] - row(r).impulseScale * *row(r).accumulated;
  };
  impulsesOf(m);
  if (axis) {
    const double total = *axis->accumulated + impulse[n];
    const bool outside = total < axis->lo || total > axis->hi;
    if (outside || (n > 0 && axis->massScale != rows[0].massScale)) {
      impulse[n] = std::clamp(total, axis->lo, axis->hi) - *axis->accumulated;
      for (int r = 0; r < n; ++r) rhs[r] += sign * f.K[r][n] * impulse[n];
      impulsesOf(n);
    }
  }
  // (Arms within range can still overflow K, as JointRows::finite.)
  double size = 0.0;
  for (int r = 0; r < m; ++r) size += std::abs(impulse[r]);
  if (!std::isfinite(size)) return;
  Vec3 p = Vec3::Zero(), dwA = Vec3::Zero(), dwB = Vec3::Zero();
  for (int r = 0; r < m; ++r) {
    *row(r).accumulated += impulse[r];
    const JointRow& jr = *row(r).row;
    p += impulse[r] * jr.lin, dwA += impulse[r] * jr.dwA, dwB += impulse[r] * jr.dwB;
  }
  jb.apply(p, dwA, dwB);
}

}  // namespace

// ---- World::Impl: the step's share ---------------------------------------------------------

// A sleeping body joined to one that moves wakes before the step (its island with it): a
// kinematic arm that starts to move carries what hangs from it. Bodies joined to each other
// fall asleep together (updateSleep), so a dynamic partner is never found asleep otherwise.
void World::Impl::wakeJoinedBodies() {
  auto moving = [](const Body& x) {
    return x.awake &&
           (x.isDynamic() || (x.type == BodyType::Kinematic && !(x.v.isZero() && x.w.isZero())));
  };
  for (const Joint& j : joints) {
    if (!j.alive) continue;
    if (moving(bodies[j.a]) && !bodies[j.b].awake) wakeBody(j.b);
    if (moving(bodies[j.b]) && !bodies[j.a].awake) wakeBody(j.a);
  }
}

// The joints with a dynamic body the solve moves, in slot order.
void World::Impl::prepareJoints() {
  solvedJoints.clear();
  for (uint32_t i = 0; i < joints.size(); ++i) {
    Joint& j = joints[i];
    if (!j.alive) continue;
    j.sa = solverIndexOf[j.a], j.sb = solverIndexOf[j.b];
    // Neither moves (static, asleep or kinematic): nothing to solve, and K would be singular.
    if (solverBodies[static_cast<size_t>(j.sa)].invMass == 0.0 &&
        solverBodies[static_cast<size_t>(j.sb)].invMass == 0.0)
      continue;
    solvedJoints.push_back(i);
  }
}

// The solved joints' rows where the bodies are now. Positions move only where the solve
// integrates them, so one frame serves a substep's warm start and biased pass (its positions
// are the last relax pass's); each body's pose and inverse inertia are found once a frame, however
// many joints it has.
void World::Impl::frameJoints() {
  if (solvedJoints.empty()) return;
  if (jointPoses.size() < bodies.size()) jointPoses.resize(bodies.size());
  const uint32_t stamp = ++jointFrameStamp;
  // Where the solve has a body now: its pose at the step's start moved by the solver body.
  auto place = [&](uint32_t slot, const SolverBody& s) -> const JointPose& {
    JointPose& p = jointPoses[slot];
    if (p.stamp == stamp) return p;
    const Body& b = bodies[slot];
    p.com = b.com + s.dp, p.q = s.dq * b.pose.q, p.R = p.q.toRotationMatrix();
    // Static, kinematic or asleep: immovable. (The solver body's inverse inertia is the step's
    // start's, as the contacts use it; with that one a ten-link chain of spinning thin links,
    // swinging in 3D, rose 1.5 % above its starting energy.)
    p.invI = s.invMass == 0.0 ? Mat3::Zero() : Mat3(p.R * b.invInertiaLocal * p.R.transpose());
    p.stamp = stamp;
    return p;
  };
  for (uint32_t i : solvedJoints) {
    Joint& j = joints[i];
    const SolverBody& A = solverBodies[static_cast<size_t>(j.sa)];
    const SolverBody& B = solverBodies[static_cast<size_t>(j.sb)];
    const JointPose &pa = place(j.a, A), &pb = place(j.b, B);
    JointFrame& f = j.frame;
    jointRows(j, pa, pb, f.rows);
    f.holds = f.rows.finite();
    if (!f.holds) continue;
    auto turns = [&](JointRow& r) { r.dwA = pa.invI * r.angA, r.dwB = pb.invI * r.angB; };
    for (int k = 0; k < f.rows.count; ++k) turns(f.rows.locked[k]);
    turns(f.rows.limit);
    const int n = f.rows.count;
    const bool axisRow = j.enableSpring || j.enableMotor || j.enableLimit;
    f.coupled = axisRow ? n + 1 : n;
    const double invMass = A.invMass + B.invMass;
    auto rowAt = [&](int r) -> const JointRow& { return r < n ? f.rows.locked[r] : f.rows.limit; };
    for (int r = 0; r < f.coupled; ++r)
      for (int c = 0; c <= r; ++c) {
        const JointRow &x = rowAt(r), &y = rowAt(c);
        f.K[r][c] = f.K[c][r] = invMass * x.lin.dot(y.lin) + x.angA.dot(y.dwA) + x.angB.dot(y.dwB);
      }
    // (Not positive definite only where K overflowed or a body's inertia is degenerate.)
    f.holds = factor(f, f.coupled);
  }
}

// Each substep starts with the impulses the joints ended the last one with (the last step's
// for the first), applied at the arms the bodies have now (Box2D's warm start; the contacts'
// comes from each body's held velocity change instead: warmStart).
void World::Impl::warmStartJoints() {
  for (uint32_t i : solvedJoints) {
    Joint& j = joints[i];
    if (!j.frame.holds) continue;
    const JointBodies jb{solverBodies[static_cast<size_t>(j.sa)],
                         solverBodies[static_cast<size_t>(j.sb)]};
    forEachHeld(j, j.frame.rows, [&](const JointRow& r, double impulse) { jb.apply(r, impulse); });
  }
}

void World::Impl::solveJoints(double h, bool useBias) {
  if (solvedJoints.empty()) return;
  const double hertz = std::min(def.jointHertz, 0.25 / h);
  const detail::Softness soft = detail::makeSoft(hertz, def.jointDampingRatio, h);
  for (uint32_t i : solvedJoints) {
    Joint& j = joints[i];
    if (!j.frame.holds) continue;
    const JointRows& rows = j.frame.rows;
    const JointBodies jb{solverBodies[static_cast<size_t>(j.sa)],
                         solverBodies[static_cast<size_t>(j.sb)]};
    // The locked rows as one block with each row along the axis in turn: the spring, the motor,
    // the nearer side of a limit (which has the last word). A limit's torque alone would turn a
    // door about its centre of mass and the hinge's rows turn it back, so solved apart they stop
    // it inexactly (a door bounced off its stop at an eighth of its speed); in the block it
    // stops dead. The axis rows cannot share a block: they are one row twice (K singular).
    const int n = rows.count;
    BlockRow block[6];
    for (int r = 0; r < n; ++r) {
      BlockRow& b = block[r];
      b.row = &rows.locked[r], b.accumulated = &j.impulse[r];
      if (!useBias) continue;
      // The drift pulled back no faster than the speed limits (a body teleported far from its
      // partner would otherwise be thrown back at any speed, and turn NaN at 1e200 m).
      const double cap = b.row->lin.isZero() ? def.maxAngularSpeed : def.maxLinearSpeed;
      b.bias = std::clamp(soft.biasRate * b.row->error, -cap, cap);
      b.massScale = soft.massScale, b.impulseScale = soft.impulseScale;
    }
    if (!j.enableSpring && !j.enableMotor && !j.enableLimit) {
      solveBlock(jb, j.frame, block, n, nullptr);
      continue;
    }
    BlockRow axisRows[3];
    int axisCount = 0;
    // Soft toward its target, once a substep: its softness is for one implicit step of h, and
    // solved in the relax pass too a 1 Hz spring lost 15 % of its swing a second (now 8 %).
    if (j.enableSpring && useBias) {
      BlockRow& b = axisRows[axisCount++];
      b.row = &rows.limit, b.accumulated = &j.springImpulse;
      const detail::Softness spring = detail::makeSoft(j.springHertz, j.springDampingRatio, h);
      b.bias = spring.biasRate * (rows.position - j.springTarget);
      b.massScale = spring.massScale, b.impulseScale = spring.impulseScale;
    }
    if (j.enableMotor) {  // rigid toward its speed, within its force
      BlockRow& b = axisRows[axisCount++];
      b.row = &rows.limit, b.accumulated = &j.motorImpulse;
      b.bias = -j.motorSpeed;
      b.hi = j.maxMotorForce * h, b.lo = -b.hi;
    }
    JointRow side;
    if (j.enableLimit) {
      // One side at a time: the other lets go of what it held.
      const bool lowerSide = rows.position - j.lower < j.upper - rows.position;
      double& other = lowerSide ? j.upperImpulse : j.lowerImpulse;
      side = lowerSide ? limitSide(rows, j.lower, 1.0) : limitSide(rows, j.upper, -1.0);
      jb.apply(side, other);  // (the other side's row is this one's, negated)
      other = 0.0;
      BlockRow& b = axisRows[axisCount++];
      b.row = &side, b.sign = lowerSide ? 1.0 : -1.0;
      b.accumulated = lowerSide ? &j.lowerImpulse : &j.upperImpulse;
      // Open, it lets the bodies close the gap within the substep and no more (speculative, as
      // Box2D's); once passed, it is soft. It only pushes.
      if (side.error > 0.0)
        b.bias = side.error / h;
      else if (useBias)
        b.bias = soft.biasRate * side.error, b.massScale = soft.massScale,
        b.impulseScale = soft.impulseScale;
      // A cone is one block with the point it turns about, soft as the point is: a ball hung
      // far from its centre turns a lot for the cone's impulse, and the point held softly
      // after a rigid stop let go 5 cm and threw the ball back faster than it came.
      if (j.type == JointType::Ball && useBias)
        b.massScale = soft.massScale, b.impulseScale = soft.impulseScale;
      b.lo = 0.0;
    }
    // A later block softens the locked rows: until then they are only held rigid.
    BlockRow rigid[6];
    if (axisCount > 1)
      for (int r = 0; r < n; ++r)
        rigid[r] = block[r], rigid[r].bias = 0.0, rigid[r].massScale = 1.0,
        rigid[r].impulseScale = 0.0;
    for (int k = 0; k < axisCount; ++k)
      solveBlock(jb, j.frame, k + 1 == axisCount ? block : rigid, n, &axisRows[k]);
  }
}

// The pairs of joined bodies that make no contacts, sorted for the narrowphase's lookup.
void World::Impl::indexJointPairs() {
  jointPairs.clear();
  for (const Joint& j : joints)
    if (j.alive && !j.collideConnected)
      jointPairs.push_back(detail::makePairKey(std::min(j.a, j.b), std::max(j.a, j.b)));
  std::sort(jointPairs.begin(), jointPairs.end());
}

// The joint in `slot` goes (its bodies wake: each is free of the other from now on); the slot
// keeps its generation for the next joint.
void World::Impl::releaseJoint(uint32_t slot) {
  Joint& j = joints[slot];
  wakeBody(j.a), wakeBody(j.b);
  const uint32_t generation = j.generation;
  j = Joint{};
  j.generation = generation;
  freeJointSlots.push_back(slot);
  --jointAliveCount;
  indexJointPairs();
}

void World::Impl::destroyJointsOf(uint32_t body) {
  for (uint32_t i = 0; i < joints.size(); ++i)
    if (joints[i].alive && (joints[i].a == body || joints[i].b == body)) releaseJoint(i);
}

// ---- World: the public calls ---------------------------------------------------------------

namespace {
const Joint& jointOf(const std::vector<Joint>& joints, JointId id, const char* field) {
  if (id.isNull() || id.index >= joints.size() || !joints[id.index].alive ||
      joints[id.index].generation != id.generation)
    throw Error(field, id.isNull() ? "is the null joint id" : "is not a live joint");
  return joints[id.index];
}

// The checks createJoint and the setters share: `owner` prefixes the value fields ("JointDef",
// "setJointLimits"), `typeField` names what asked a joint without an axis position for one.
void requireAxisPosition(JointType type, const char* what, const std::string& typeField) {
  if (!hasAxisPosition(type))
    throw Error(typeField, std::string("only hinges, sliders and distance joints have ") + what);
}
void checkLimit(JointType type, double lower, double upper, const std::string& owner,
                const std::string& typeField) {
  requireFinite(lower, (owner + ".lower").c_str());
  requireFinite(upper, (owner + ".upper").c_str());
  requireAxisPosition(type, "limits", typeField);
  if (lower > upper) throw Error(owner + ".lower", "must not exceed upper");
  if (type == JointType::Hinge && (lower < -kPi || upper > kPi))
    throw Error(owner + (lower < -kPi ? ".lower" : ".upper"), "must be within [-pi, pi]");
}
void checkMotor(JointType type, double speed, double maxForce, const std::string& owner,
                const std::string& typeField) {
  requireAxisPosition(type, "motors", typeField);
  requireFinite(speed, (owner + ".motorSpeed").c_str());
  requireNonNegative(maxForce, (owner + ".maxMotorForce").c_str());
}
void checkSpring(JointType type, double hertz, double dampingRatio, double target,
                 const std::string& owner, const std::string& typeField) {
  requireAxisPosition(type, "springs", typeField);
  requirePositive(hertz, (owner + ".springHertz").c_str());
  requireNonNegative(dampingRatio, (owner + ".springDampingRatio").c_str());
  requireFinite(target, (owner + ".springTarget").c_str());
}
}  // namespace

JointId World::createJoint(const JointDef& d) {
  Impl& w = *impl_;
  const Body& A = w.body(d.a, "JointDef.a");
  const Body& B = w.body(d.b, "JointDef.b");
  if (d.a == d.b) throw Error("JointDef.b", "must be another body than a");
  if (!A.isDynamic() && !B.isDynamic()) throw Error("JointDef", "needs a dynamic body");
  requireFinite(d.anchor, "JointDef.anchor");
  requireFinite(d.axis, "JointDef.axis");
  if (d.type == JointType::Distance) {
    requireFinite(d.anchorB, "JointDef.anchorB");
    if (!((d.anchorB - d.anchor).norm() > 1e-6))
      throw Error("JointDef.anchorB", "must be apart from anchor (a distance joint's length)");
  }
  const double length = d.axis.norm();
  if (!(length > 1e-12) || !std::isfinite(length))
    throw Error("JointDef.axis", "must have a length above zero");
  if (d.enableLimit) checkLimit(d.type, d.lower, d.upper, "JointDef", "JointDef.enableLimit");
  if (d.enableCone) {
    if (d.type != JointType::Ball)
      throw Error("JointDef.enableCone", "only ball joints have a cone");
    requireFinite(d.coneAngle, "JointDef.coneAngle");
    if (!(d.coneAngle > 0.0 && d.coneAngle < kPi))
      throw Error("JointDef.coneAngle", "must be within (0, pi)");
  }
  if (d.enableMotor)
    checkMotor(d.type, d.motorSpeed, d.maxMotorForce, "JointDef", "JointDef.enableMotor");
  // Positive; infinity (the default) never breaks.
  if (!(d.breakForce > 0.0))
    throw Error("JointDef.breakForce", "must be positive (infinity: never breaks)");
  if (!(d.breakTorque > 0.0))
    throw Error("JointDef.breakTorque", "must be positive (infinity: never breaks)");
  if (d.enableSpring)
    checkSpring(d.type, d.springHertz, d.springDampingRatio, d.springTarget, "JointDef",
                "JointDef.enableSpring");

  Joint j;
  j.alive = true;
  j.type = d.type;
  j.a = d.a.index, j.b = d.b.index;
  const Vec3 axis = d.axis / length;
  const Vec3 anchorB = d.type == JointType::Distance ? d.anchorB : d.anchor;
  j.localA = A.pose.q.conjugate() * (d.anchor - A.com);
  j.localB = B.pose.q.conjugate() * (anchorB - B.com);
  j.restLength = (anchorB - d.anchor).norm();
  j.axisA = A.pose.q.conjugate() * axis;
  j.axisB = B.pose.q.conjugate() * axis;
  j.reference = A.pose.q.conjugate() * B.pose.q;
  j.enableLimit = d.enableLimit, j.collideConnected = d.collideConnected;
  j.lower = d.lower, j.upper = d.upper;
  // A ball joint's cone is its limit on the swing (in [0, pi]): only the upper side ever holds.
  if (d.enableCone) j.enableLimit = true, j.lower = -kPi, j.upper = d.coneAngle;
  j.enableMotor = d.enableMotor, j.motorSpeed = d.motorSpeed, j.maxMotorForce = d.maxMotorForce;
  j.enableSpring = d.enableSpring, j.springHertz = d.springHertz;
  j.springDampingRatio = d.springDampingRatio, j.springTarget = d.springTarget;
  j.breakForce = d.breakForce, j.breakTorque = d.breakTorque;

  uint32_t slot;
  if (!w.freeJointSlots.empty()) {
    slot = w.freeJointSlots.back();
    w.freeJointSlots.pop_back();
    j.generation = w.joints[slot].generation + 1;
    if (j.generation == 0) j.generation = 1;
    w.joints[slot] = j;
  } else {
    slot = static_cast<uint32_t>(w.joints.size());
    j.generation = 1;
    w.joints.push_back(j);
  }
  ++w.jointAliveCount;
  w.indexJointPairs();
  // Both wake: their contacts with each other go (or stay) from the next step, and each starts
  // to feel the other.
  w.wakeBody(j.a), w.wakeBody(j.b);
  return JointId{slot, w.joints[slot].generation};
}

void World::destroyJoint(JointId id) {
  jointOf(impl_->joints, id, "destroyJoint.id");
  impl_->releaseJoint(id.index);
}

bool World::isValid(JointId id) const {
  return !id.isNull() && id.index < impl_->joints.size() && impl_->joints[id.index].alive &&
         impl_->joints[id.index].generation == id.generation;
}

int World::jointCount() const {
  return impl_->jointAliveCount;
}

JointType World::jointType(JointId id) const {
  return jointOf(impl_->joints, id, "jointType.id").type;
}

double World::jointPosition(JointId id) const {
  const Joint& j = jointOf(impl_->joints, id, "jointPosition.id");
  if (!hasAxisPosition(j.type))
    throw Error("jointPosition.id", "only hinges, sliders and distance joints have a position");
  JointRows rows;
  jointRows(j, poseOf(impl_->bodies[j.a]), poseOf(impl_->bodies[j.b]), rows);
  return rows.position;
}

double World::jointSpeed(JointId id) const {
  const Joint& j = jointOf(impl_->joints, id, "jointSpeed.id");
  if (!hasAxisPosition(j.type))
    throw Error("jointSpeed.id", "only hinges, sliders and distance joints have a position");
  const Body &A = impl_->bodies[j.a], &B = impl_->bodies[j.b];
  JointRows rows;
  jointRows(j, poseOf(A), poseOf(B), rows);
  const JointRow& r = rows.limit;
  return r.lin.dot(B.v - A.v) + r.angB.dot(B.w) - r.angA.dot(A.w);
}

// Applies a change to a joint's limit, motor or spring and wakes its bodies. A distance joint
// is a rod while it has none of them: the rod's row comes and goes with them, starting afresh
// each time, and holds the length the joint has when it comes (a winch stopped, a rope whose
// limit was taken off), not the one it was made with.
template <class Change>
void World::Impl::changeAxisDrive(uint32_t slot, const Change& change) {
  Joint& j = joints[slot];
  const auto isRod = [](const Joint& k) {
    return k.type == JointType::Distance && !k.enableLimit && !k.enableSpring && !k.enableMotor;
  };
  const bool wasRod = isRod(j);
  JointRows rows;
  if (j.type == JointType::Distance) jointRows(j, poseOf(bodies[j.a]), poseOf(bodies[j.b]), rows);
  change(j);
  if (isRod(j) != wasRod) {
    j.impulse[0] = 0.0;
    if (isRod(j)) j.rodStretch = rows.position;
  }
  wakeBody(j.a), wakeBody(j.b);
}

void World::setJointMotor(JointId id, bool enable, double speed, double maxForce) {
  const Joint& found = jointOf(impl_->joints, id, "setJointMotor.id");
  if (!hasAxisPosition(found.type))
    throw Error("setJointMotor.id", "only hinges, sliders and distance joints have motors");
  requireFinite(speed, "setJointMotor.speed");
  requireNonNegative(maxForce, "setJointMotor.maxForce");
  impl_->changeAxisDrive(id.index, [&](Joint& j) {
    j.enableMotor = enable, j.motorSpeed = speed, j.maxMotorForce = maxForce;
    if (!enable) j.motorImpulse = 0.0;
  });
}

void World::setJointLimits(JointId id, bool enable, double lower, double upper) {
  const Joint& found = jointOf(impl_->joints, id, "setJointLimits.id");
  if (enable)
    checkLimit(found.type, lower, upper, "setJointLimits", "setJointLimits.id");
  else
    requireAxisPosition(found.type, "limits", "setJointLimits.id");
  impl_->changeAxisDrive(id.index, [&](Joint& j) {
    // New limits start afresh (as Box2D's): what the old ones held may push the wrong way now.
    if (enable != j.enableLimit || lower != j.lower || upper != j.upper)
      j.lowerImpulse = 0.0, j.upperImpulse = 0.0;
    j.enableLimit = enable;
    if (enable) j.lower = lower, j.upper = upper;
  });
}

void World::setJointSpring(JointId id, bool enable, double springHertz, double springDampingRatio,
                           double springTarget) {
  const Joint& found = jointOf(impl_->joints, id, "setJointSpring.id");
  if (enable)
    checkSpring(found.type, springHertz, springDampingRatio, springTarget, "setJointSpring",
                "setJointSpring.id");
  else
    requireAxisPosition(found.type, "springs", "setJointSpring.id");
  impl_->changeAxisDrive(id.index, [&](Joint& j) {
    j.enableSpring = enable;
    if (enable) j.springHertz = springHertz, j.springDampingRatio = springDampingRatio;
    if (enable)
      j.springTarget = springTarget;
    else
      j.springImpulse = 0.0;
  });
}

void World::setJointLength(JointId id, double length) {
  const Joint& found = jointOf(impl_->joints, id, "setJointLength.id");
  if (found.type != JointType::Distance)
    throw Error("setJointLength.id", "only distance joints have a length");
  requirePositive(length, "setJointLength.length");
  Joint& j = impl_->joints[id.index];
  // The rod, the rope's limits and the spring's target count from the new length.
  j.restLength = length, j.rodStretch = 0.0;
  impl_->wakeBody(j.a), impl_->wakeBody(j.b);
}

namespace {
// The force a joint exerted on b over the last substep and its torque about b's anchor: each
// row's angular impulse on b is about b's centre, where its linear one has the moment
// arm x lin, which about the anchor is not felt.
struct Wrench {
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
};
Wrench heldWrench(const Joint& j, const std::vector<Body>& bodies, double substep) {
  if (substep == 0.0) return {};
  const JointPose b = poseOf(bodies[j.b]);
  JointRows rows;
  jointRows(j, poseOf(bodies[j.a]), b, rows);
  const Vec3 arm = b.R * j.localB;
  Wrench w;
  forEachHeld(j, rows, [&](const JointRow& r, double held) {
    w.force += held * r.lin, w.torque += held * (r.angB - arm.cross(r.lin));
  });
  w.force /= substep, w.torque /= substep;
  return w;
}
}  // namespace

// Joints that held more than they can break, in slot order, after the step (so jointForce and
// jointTorque read then give what broke them).
void World::Impl::breakJoints() {
  for (uint32_t i = 0; i < joints.size(); ++i) {
    const Joint& j = joints[i];
    if (!j.alive || (std::isinf(j.breakForce) && std::isinf(j.breakTorque))) continue;
    const Wrench held = heldWrench(j, bodies, lastSubstep);
    if (!(held.force.norm() > j.breakForce) && !(held.torque.norm() > j.breakTorque)) continue;
    jointBreaks.push_back(
        {JointId{i, j.generation}, idOf(j.a), idOf(j.b), held.force, held.torque});
    releaseJoint(i);
  }
}

Vec3 World::jointForce(JointId id) const {
  const Joint& j = jointOf(impl_->joints, id, "jointForce.id");
  return heldWrench(j, impl_->bodies, impl_->lastSubstep).force;
}

Vec3 World::jointTorque(JointId id) const {
  const Joint& j = jointOf(impl_->joints, id, "jointTorque.id");
  return heldWrench(j, impl_->bodies, impl_->lastSubstep).torque;
}

}  // namespace grip
