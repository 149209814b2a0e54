// The solve stage: a soft-step contact solver in the style of Box2D v3 (Catto, "Solver2D"),
// in 3D. Per substep: integrate velocities, warm start, solve with bias, integrate positions,
// relax (solve without bias; the last relax pass propagates support from the ground up),
// hand held loads down (the load pass). Then one restitution pass, a position projection,
// and the impulses are stored for the next step's warm start. docs/dynamics.md explains the
// choices and the measurements.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>

#include "dynamics/detail/world_impl.hpp"

namespace grip {

using detail::Body;
using detail::ContactManifold;
using detail::kAcross;
using detail::kNoRegion;
using detail::kRegionBodies;
using detail::makeSoft;
using detail::Softness;
using detail::SolverBody;
using detail::SolverManifold;
using detail::SolverRow;

namespace {

constexpr int kColdPasses = 4;  // relax passes for a touching new contact in its first substep
constexpr double kMaxProjection = 0.05;  // m, the most one projection push moves a point
constexpr double kTiltSlop = 0.3;  // of positionSlop: the patch tilt the projection leaves alone
constexpr double kMinPatchSpread = 1e-4;  // m: points spread less get no exact patch solve
constexpr int kDirectRows =
    64;  // largest island (in normal rows) whose normals are solved directly
// Manifolds a moving body has room for before the list grows: a landing pile of boxes peaks at
// about four a body (touching and speculative), so twice that.
constexpr size_t kManifoldsPerBody = 8;

struct SolveContext {
  double invH = 0.0, slop = 0.0, pushout = 0.0;
  double touching = 0.0;  // a pushing point this near stays touching (def.positionSlop)
  int manifoldSweeps = 4;
  double breakVelocity = 0.0;
  double restingSpeed = 0.0;  // a body slower than this on its support rests (the load pass)
  double supportSpeed = 0.0;  // faster across a contact, a body is no support (shock pass)
  Softness soft, staticSoft, anchorSoft;
  int worldTwin = 0;  // region 1's world (World::Impl::splitRegions)
  bool onWorld(const SolverManifold& m) const {
    return m.a == 0 || m.b == 0 || m.a == worldTwin || m.b == worldTwin;
  }
};

// Which bodies a solve may move. Shock propagation freezes the body nearer the ground.
enum class Moves : uint8_t { Both = 0, OnlyA = 1, OnlyB = 2 };  // as SolverManifold::shockMoves

inline double rowVelocity(const SolverBody& a, const SolverBody& b, const SolverRow& r) {
  return r.lin.dot(b.v - a.v) + r.angB.dot(b.w) - r.angA.dot(a.w);
}

inline void applyRow(SolverBody& a, SolverBody& b, const SolverRow& r, double impulse,
                     Moves moves = Moves::Both) {
  if (moves != Moves::OnlyB) {
    a.v -= (a.invMass * impulse) * r.lin;
    a.w -= impulse * r.dwA;
  }
  if (moves != Moves::OnlyA) {
    b.v += (b.invMass * impulse) * r.lin;
    b.w += impulse * r.dwB;
  }
}

// Where an impulse's change to a body goes: its velocities, or, for the body a shock pass holds
// still, aside: the next substep's warm start still gives that body the reaction, as it applies
// every accumulated impulse to both bodies (World::Impl::warmStart).
struct Velocity {
  Vec3& v;
  Vec3& w;
};
inline Velocity velocityOf(SolverBody& b, bool held) {
  return held ? Velocity{b.heldV, b.heldW} : Velocity{b.v, b.w};
}

inline double inverseMass(const SolverBody& a, const SolverBody& b, const SolverRow& r,
                          Moves moves) {
  const double lin2 = r.lin.squaredNorm();
  double k = 0.0;
  if (moves != Moves::OnlyB) k += a.invMass * lin2 + r.angA.dot(r.dwA);
  if (moves != Moves::OnlyA) k += b.invMass * lin2 + r.angB.dot(r.dwB);
  return k;
}

// Effective mass of a row when only some bodies move.
inline double rowMass(const SolverBody& a, const SolverBody& b, const SolverRow& r, Moves moves) {
  if (moves == Moves::Both) return r.mass;
  const double k = inverseMass(a, b, r, moves);
  return k > 0.0 ? 1.0 / k : 0.0;
}

SolverRow makeRow(const SolverBody& a, const SolverBody& b, const Vec3& lin, const Vec3& angA,
                  const Vec3& angB) {
  SolverRow r;
  r.lin = lin, r.angA = angA, r.angB = angB;
  r.dwA = a.invI * angA, r.dwB = b.invI * angB;
  const double k = inverseMass(a, b, r, Moves::Both);
  r.mass = k > 0.0 ? 1.0 / k : 0.0;
  return r;
}

// Coulomb friction for the patch: the tangential impulse is capped by a circular cone of
// mu times the patch's total normal impulse, the twist by the same times the patch radius.
// Static friction (mu_s) holds until the cap is reached in a relax pass (when the normal
// impulses were solved this substep); from then on the patch slides with mu_d.
bool solveFriction(SolverManifold& m, SolverBody& A, SolverBody& B, const SolveContext& ctx,
                   bool useBias, Moves moves, bool mayBreak) {
  double normal = 0.0;
  for (int k = 0; k < m.count; ++k) normal += m.impulse[k];
  const double mu = m.sliding ? m.dynamicFriction : m.staticFriction;
  SolverRow &t1 = m.friction[0], &t2 = m.friction[1], &twist = m.friction[2];
  // No push, no friction: a patch that does not press and holds no friction impulse has
  // nothing to do (most speculative contacts of a falling pile).
  if (normal == 0.0 && t1.impulse == 0.0 && t2.impulse == 0.0 && twist.impulse == 0.0) return false;
  const double old1 = t1.impulse, old2 = t2.impulse;
  // A sticking patch is pulled back to its anchor softly in the biased pass (the drift is
  // linearised in the bodies' motion since the step began, as separations are).
  double bias1 = 0.0, bias2 = 0.0;
  if (useBias && !m.sliding && m.anchored) {
    const Vec3 dp = B.dp - A.dp;
    const double e1 =
        m.anchorError[0] + t1.lin.dot(dp) + t1.angB.dot(B.dtheta) - t1.angA.dot(A.dtheta);
    const double e2 =
        m.anchorError[1] + t2.lin.dot(dp) + t2.angB.dot(B.dtheta) - t2.angA.dot(A.dtheta);
    bias1 = ctx.anchorSoft.biasRate * e1, bias2 = ctx.anchorSoft.biasRate * e2;
  }
  const double scale = useBias && !m.sliding && m.anchored ? ctx.anchorSoft.massScale : 1.0;
  const bool both = moves == Moves::Both;
  const double mass1 = both ? t1.mass : m.shockFrictionMass[0];
  const double mass2 = both ? t2.mass : m.shockFrictionMass[1];
  const Vec3 dv = B.v - A.v;
  auto velocity = [&](const SolverRow& r) {
    return r.lin.dot(dv) + r.angB.dot(B.w) - r.angA.dot(A.w);
  };
  double n1 = old1 - scale * mass1 * (velocity(t1) + bias1);
  double n2 = old2 - scale * mass2 * (velocity(t2) + bias2);
  const double limit = mu * normal;
  const double len2 = n1 * n1 + n2 * n2;
  const bool capped = len2 > limit * limit;
  if (capped) {
    const double s = limit > 0.0 ? limit / std::sqrt(len2) : 0.0;
    n1 *= s, n2 *= s;
  }
  t1.impulse = n1, t2.impulse = n2;
  // Both tangent impulses as one linear and one angular change per body.
  const double d1 = n1 - old1, d2 = n2 - old2;
  const Vec3 linear = d1 * t1.lin + d2 * t2.lin;
  const Velocity a = velocityOf(A, moves == Moves::OnlyB), b = velocityOf(B, moves == Moves::OnlyA);
  a.v -= A.invMass * linear, a.w -= d1 * t1.dwA + d2 * t2.dwA;
  b.v += B.invMass * linear, b.w += d1 * t1.dwB + d2 * t2.dwB;
  // Breaking loose means the cone cannot stop the patch: still moving after the capped
  // impulse. Capped while arresting a small residual motion is still sticking.
  if (capped && mayBreak && !m.sliding) {
    const double v1 = rowVelocity(A, B, t1), v2 = rowVelocity(A, B, t2);
    m.sliding = v1 * v1 + v2 * v2 > ctx.breakVelocity * ctx.breakVelocity;
  }
  if (m.count > 1) {
    const double oldT = twist.impulse, maxT = mu * normal * m.twistRadius;
    const double massT = both ? twist.mass : m.shockFrictionMass[2];
    const double spin = twist.angB.dot(B.w) - twist.angA.dot(A.w);  // the twist has no lin
    const double nt = std::clamp(oldT - massT * spin, -maxT, maxT);
    twist.impulse = nt;
    a.w -= (nt - oldT) * twist.dwA;
    b.w += (nt - oldT) * twist.dwB;
  }
  return true;
}

// The coupling Jb M^-1 Jb^T of a manifold's three basis rows (centre normal, rotation about
// t1, about t2) through the bodies that move.
void basisCoupling(const SolverManifold& m, const SolverBody& a, const SolverBody& b, Moves moves,
                   double (&k)[3][3]) {
  const Vec3 &t1 = m.friction[0].lin, &t2 = m.friction[1].lin;
  double k00 = 0.0, k01 = 0.0, k02 = 0.0, k11 = 0.0, k12 = 0.0, k22 = 0.0;
  if (moves != Moves::OnlyB) {
    k00 += a.invMass + m.armA.dot(m.dwA);
    k01 += m.armA.dot(m.spinA[0]), k02 += m.armA.dot(m.spinA[1]);
    k11 += t1.dot(m.spinA[0]), k12 += t1.dot(m.spinA[1]), k22 += t2.dot(m.spinA[1]);
  }
  if (moves != Moves::OnlyA) {
    k00 += b.invMass + m.armB.dot(m.dwB);
    k01 += m.armB.dot(m.spinB[0]), k02 += m.armB.dot(m.spinB[1]);
    k11 += t1.dot(m.spinB[0]), k12 += t1.dot(m.spinB[1]), k22 += t2.dot(m.spinB[1]);
  }
  k[0][0] = k00, k[0][1] = k[1][0] = k01, k[0][2] = k[2][0] = k02;
  k[1][1] = k11, k[1][2] = k[2][1] = k12, k[2][2] = k22;
}

// The points' normal coupling K_ij = J_i M^-1 J_j^T = c_i . Kb c_j, with c_k = (1, alpha_k,
// beta_k).
template <int N>
void pointCoupling(const SolverManifold& m, const double (&kb)[3][3], double (&K)[4][4]) {
  double kc[4][3];
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < 3; ++i) kc[j][i] = kb[i][0] + kb[i][1] * m.alpha[j] + kb[i][2] * m.beta[j];
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) K[i][j] = kc[j][0] + m.alpha[i] * kc[j][1] + m.beta[i] * kc[j][2];
}

// The points' coupling K (and for the shock pass the point masses 1 / K_kk) for the bodies a
// solve moves, prepared the first time a solve needs them: a face patch that the exact patch
// solve handles never does.
template <int N>
const double (*pointCouplings(SolverManifold& m, bool both))[4] {
  if (both) {
    if (!m.couplingReady) pointCoupling<N>(m, m.basisK, m.K), m.couplingReady = true;
    return m.K;
  }
  if (!m.shockCouplingReady) {
    pointCoupling<N>(m, m.shockBasisK, m.shockK);
    for (int k = 0; k < N; ++k)
      m.shockPointMass[k] = m.shockK[k][k] > 0.0 ? 1.0 / m.shockK[k][k] : 0.0;
    m.shockCouplingReady = true;
  }
  return m.shockK;
}

// The three basis rows' velocities: centre normal, relative spin about t1 and about t2.
inline void basisVelocity(const SolverManifold& m, const SolverBody& A, const SolverBody& B,
                          double linearVelocity, double (&g)[3]) {
  const Vec3 spin = B.w - A.w;
  g[0] = linearVelocity + m.armB.dot(B.w) - m.armA.dot(A.w);
  g[1] = m.friction[0].lin.dot(spin), g[2] = m.friction[1].lin.dot(spin);
}

// Point impulses given by their sums (sum l, sum alpha l, sum beta l) applied to the bodies.
inline void applyBasis(const SolverManifold& m, SolverBody& A, SolverBody& B, const double (&L)[3],
                       Moves moves) {
  const Velocity a = velocityOf(A, moves == Moves::OnlyB), b = velocityOf(B, moves == Moves::OnlyA);
  a.v -= (A.invMass * L[0]) * m.normal;
  a.w -= L[0] * m.dwA + L[1] * m.spinA[0] + L[2] * m.spinA[1];
  b.v += (B.invMass * L[0]) * m.normal;
  b.w += L[0] * m.dwB + L[1] * m.spinB[0] + L[2] * m.spinB[1];
}

// The normal row of point k written out, for the paths that work row by row.
SolverRow pointRow(const SolverManifold& m, int k) {
  const Vec3 arm = m.alpha[k] * m.friction[0].lin + m.beta[k] * m.friction[1].lin;
  SolverRow r;
  r.lin = m.normal;
  r.angA = m.armA + arm, r.angB = m.armB + arm;
  r.dwA = m.dwA + m.alpha[k] * m.spinA[0] + m.beta[k] * m.spinA[1];
  r.dwB = m.dwB + m.alpha[k] * m.spinB[0] + m.beta[k] * m.spinB[1];
  r.mass = m.pointMass[k];
  r.impulse = m.impulse[k];
  return r;
}

// The basis coupling inverted; false if it is not positive definite.
bool invertBlock(const double (&kb)[3][3], double (&out)[3][3]) {
  const Mat3 k = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&kb[0][0]);
  const double det = k.determinant(), trace = k.trace();
  if (!(det > 1e-12 * trace * trace * trace)) return false;
  const Mat3 inv = k.inverse();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = inv(i, j);
  return true;
}

// Prepares the exact patch solve of a manifold of 3 or 4 points: each point's normal velocity
// is g0 + alpha_k g1 + beta_k g2 in the basis rows' velocities g.
void prepareBlock(SolverManifold& m) {
  m.block = false;
  if (m.count < 3) return;
  double saa = 0.0, sab = 0.0, sbb = 0.0;
  for (int k = 0; k < m.count; ++k) {
    saa += m.alpha[k] * m.alpha[k], sab += m.alpha[k] * m.beta[k], sbb += m.beta[k] * m.beta[k];
  }
  // Points near a line leave a rotation unconstrained: no exact patch solve then. Nor points
  // (nearly) at one place: the test is relative, and three copies of one point (arms of
  // 1e-17 m) passed it; the fit, of order 1/det, stored impulses of 1e14 on them, and the next
  // step's warm start flung a pile of hulls apart.
  const double det = saa * sbb - sab * sab;
  if (!(saa + sbb > kMinPatchSpread * kMinPatchSpread)) return;
  if (!(det > 1e-4 * (saa + sbb) * (saa + sbb))) return;
  if (!invertBlock(m.basisK, m.blockInv)) return;
  // fit = (C^T C)^-1 C^T for C_k = (1, alpha_k, beta_k); the centre makes sum alpha = 0.
  for (int k = 0; k < m.count; ++k) {
    m.fit[0][k] = 1.0 / m.count;
    m.fit[1][k] = (sbb * m.alpha[k] - sab * m.beta[k]) / det;
    m.fit[2][k] = (saa * m.beta[k] - sab * m.alpha[k]) / det;
    m.slack[k] = 0.0;
  }
  if (m.count == 4) {  // the null vector of C^T: cofactors of C
    for (int k = 0; k < 4; ++k) {
      Mat3 minor;
      for (int r = 0, row = 0; r < 4; ++r) {
        if (r == k) continue;
        minor.row(row++) << 1.0, m.alpha[r], m.beta[r];
      }
      m.slack[k] = (k % 2 ? -1.0 : 1.0) * minor.determinant();
    }
    const double len = std::sqrt(m.slack[0] * m.slack[0] + m.slack[1] * m.slack[1] +
                                 m.slack[2] * m.slack[2] + m.slack[3] * m.slack[3]);
    if (!(len > 0.0)) return;
    // A point the slack barely moves (rounding, where two points coincide) is held: lifting
    // it along the slack would take a huge shift (one gave an impulse of 3e17).
    for (double& x : m.slack) x = std::abs(x) < 1e-6 * len ? 0.0 : x / len;
  }
  m.block = true;
}

// The exact solve of a patch whose rows are all rigid with targets `bias`: the basis velocities
// g are driven to the least-squares fit of the targets, and the new total impulses are spread
// over the points (the least change, shifted along the slack if a point would pull). False,
// with nothing applied, if no spread keeps every point pushing.
template <int N>
bool solveNormalBlock(SolverManifold& m, SolverBody& A, SolverBody& B, const double (&g)[3],
                      const double* bias, Moves moves) {
  double dg[3];
  for (int i = 0; i < 3; ++i) {
    double target = 0.0;
    for (int k = 0; k < N; ++k) target -= m.fit[i][k] * bias[k];
    dg[i] = target - g[i];
  }
  const double(*inv)[3] = moves == Moves::Both ? m.blockInv : m.shockBlockInv;
  double dT[3];
  for (int i = 0; i < 3; ++i) dT[i] = inv[i][0] * dg[0] + inv[i][1] * dg[1] + inv[i][2] * dg[2];
  double lambda[4], along = 0.0;
  for (int k = 0; k < N; ++k) {
    lambda[k] = m.impulse[k] + m.fit[0][k] * dT[0] + m.fit[1][k] * dT[1] + m.fit[2][k] * dT[2];
    along += lambda[k] * m.slack[k];
  }
  // The even spread (least norm) of the new totals, unless a point would pull.
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  bool pulls = false;
  for (int k = 0; k < N; ++k) {
    lambda[k] -= along * m.slack[k];
    pulls |= lambda[k] < 0.0;
    // lambda_k + t slack_k >= 0 bounds the shift t.
    if (m.slack[k] > 0.0) lo = std::max(lo, -lambda[k] / m.slack[k]);
    if (m.slack[k] < 0.0) hi = std::min(hi, -lambda[k] / m.slack[k]);
    if (m.slack[k] == 0.0 && lambda[k] < 0.0) hi = lo - 1.0;
  }
  if (pulls) {
    if (N < 4 || lo > hi) return false;
    const double t = std::clamp(0.0, lo, hi);
    for (int k = 0; k < N; ++k) lambda[k] = std::max(lambda[k] + t * m.slack[k], 0.0);
  }
  for (int k = 0; k < N; ++k) {
    m.maxImpulse[k] = std::max(m.maxImpulse[k], lambda[k] - m.impulse[k]);
    m.impulse[k] = lambda[k];
  }
  applyBasis(m, A, B, dT, moves);
  return true;
}

// Solves a x = r for the leading n x n block of a (n <= 3) by Cramer's rule; false if a is
// too close to singular.
bool solveSmall(const double (&a)[3][3], const double* r, int n, double* x) {
  if (n == 1) {
    if (!(a[0][0] > 0.0)) return false;
    x[0] = r[0] / a[0][0];
    return true;
  }
  if (n == 2) {
    const double det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    if (!(det > 1e-9 * (a[0][0] + a[1][1]) * (a[0][0] + a[1][1]))) return false;
    x[0] = (r[0] * a[1][1] - a[0][1] * r[1]) / det;
    x[1] = (a[0][0] * r[1] - r[0] * a[1][0]) / det;
    return true;
  }
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
  const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
  const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  const double trace = a[0][0] + a[1][1] + a[2][2];
  if (!(det > 1e-9 * trace * trace * trace)) return false;
  const Mat3 inv =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&a[0][0]).inverse();
  for (int i = 0; i < 3; ++i) x[i] = inv(i, 0) * r[0] + inv(i, 1) * r[1] + inv(i, 2) * r[2];
  return true;
}

// The normal impulses of a manifold's rigid rows solved exactly for a guessed set of pushing
// points (those pushing already or closing faster than allowed; at most three, as four points
// of a face go to the patch solve): the others, which hold no impulse and do not close, stay
// let go, the pushing ones solved together. True, with `delta` set, if every pushing point
// still pushes. A let-go point that the others' impulses make close waits for the next pass.
// (Letting the pulling points go and solving again until the set holds, with or without
// taking back let-go points that close, made the 18-layer Jenga tower drift 0.23-0.27 mm
// where its test allows 0.1 mm: docs/performance.md.)
template <int N>
bool solveNormalActive(const SolverManifold& m, const double (*K)[4], const double* vn,
                       const double* bias, double* delta) {
  int active[4], na = 0;
  for (int k = 0; k < N; ++k) {
    const bool pushing = m.impulse[k] > 0.0 || vn[k] + bias[k] < 0.0;
    if (pushing) active[na++] = k;
    delta[k] = pushing ? 0.0 : -m.impulse[k];
  }
  if (na == 4) return false;
  double a[3][3], r[3], x[3];
  for (int i = 0; i < na; ++i) {
    const int k = active[i];
    r[i] = -(vn[k] + bias[k]);
    for (int j = 0; j < N; ++j) r[i] -= K[k][j] * delta[j];
    for (int j = 0; j < na; ++j) a[i][j] = K[k][active[j]];
  }
  if (na > 0 && !solveSmall(a, r, na, x)) return false;
  for (int i = 0; i < na; ++i) {
    if (m.impulse[active[i]] + x[i] < 0.0) return false;
    delta[active[i]] = x[i];
  }
  return true;
}

// Gauss-Seidel sweeps over a manifold's N points: each point's impulse solved against the
// others' current ones (soft rows scaled), clamped to push only.
struct Sweep {
  const double (*K)[4];
  const double *vn, *bias, *mass, *massScale, *impulseScale, *impulse;
};
template <int N>
void gaussSeidel(const Sweep& s, int sweeps, double* delta) {
  for (int it = 0; it < sweeps; ++it) {
    for (int k = 0; k < N; ++k) {
      double v = s.vn[k];
      for (int j = 0; j < N; ++j) v += s.K[k][j] * delta[j];
      const double total = s.impulse[k] + delta[k];
      const double impulse =
          -s.mass[k] * s.massScale[k] * (v + s.bias[k]) - s.impulseScale[k] * total;
      delta[k] = std::max(total + impulse, 0.0) - s.impulse[k];
    }
  }
}

// Whether a manifold is certainly idle (no point pushes, each closes slower than its gap
// allows), from bounds on every point's separation and normal velocity: the per-point test
// below costs more, and half the manifolds of a pile are such gaps. The margin keeps this an
// under-estimate of the exact test, so both give the same result. A bouncy manifold's biased
// pass records the approach speed, so it takes the full path.
inline bool idleByBounds(const SolverManifold& m, const SolverBody& A, const SolverBody& B,
                         const SolveContext& ctx, bool useBias, double linearVelocity,
                         double linearShift) {
  if (useBias && m.bouncy) return false;
  // A manifold without rows holds no impulse (prepareManifold); one with rows is checked.
  if (m.rowsReady)
    for (int k = 0; k < m.count; ++k)
      if (m.impulse[k] != 0.0) return false;
  const double gap = m.minSeparation + linearShift - m.reachA * A.turned - m.reachB * B.turned;
  if (!(gap > 1e-12)) return false;
  const double approach = linearVelocity - m.reachA * A.w.norm() - m.reachB * B.w.norm();
  return approach + gap * ctx.invH > 1e-9;
}

// Non-penetration. The points of one manifold push on the same two bodies, so they are
// solved together, in the patch basis: exactly where a guess of the pushing points holds (a
// face's points by the patch solve, fewer by a small dense solve), else by a few Gauss-Seidel
// sweeps over the manifold's own small system K. Solving them one at a time against the
// bodies leaves the first point with most of the load and tips the body.
template <int N>
bool solveNormalN(SolverManifold& m, SolverBody& A, SolverBody& B, const SolveContext& ctx,
                  bool useBias, Moves moves) {
  const Vec3& n = m.normal;
  const double linearVelocity = n.dot(B.v - A.v), linearShift = n.dot(B.dp - A.dp);
  if (idleByBounds(m, A, B, ctx, useBias, linearVelocity, linearShift)) return false;
  const Softness& soft = ctx.onWorld(m) ? ctx.staticSoft : ctx.soft;
  // The basis velocities, and the basis displacements since the step began.
  double g[3];
  basisVelocity(m, A, B, linearVelocity, g);
  const Vec3 turn = B.dtheta - A.dtheta;
  const double shift = linearShift + m.armB.dot(B.dtheta) - m.armA.dot(A.dtheta);
  const double turn1 = m.friction[0].lin.dot(turn), turn2 = m.friction[1].lin.dot(turn);
  // (Fixed-size zeroing: a loop of count zero stores becomes a memset call.)
  double vn[4], bias[4], delta[4] = {0.0, 0.0, 0.0, 0.0};
  bool rigid = true, idle = true;
  uint8_t softRows = 0;  // bit k: row k pushes out softly
  int speculative = 0;
  for (int k = 0; k < N; ++k) {
    // Current separation, linearised in the bodies' motion since the step began.
    const double s = m.separation[k] + shift + m.alpha[k] * turn1 + m.beta[k] * turn2;
    double b = 0.0;
    // A point that pushes stays touching across a gap within positionSlop (depths within it
    // are not told apart, as the position projection leaves such overlaps alone). Letting it
    // close the gap instead handed a body's load to whichever support stood a few micrometres
    // higher, more so the more passes (docs/dynamics.md, the Jenga tower).
    if (s > 0.0 && !(s <= ctx.touching && m.impulse[k] > 0.0)) {
      b = s * ctx.invH;  // speculative: may close the gap, no more
    } else if (useBias && s < -ctx.slop) {
      // Overlap beyond the slop: pushed out softly. Within the slop the contact is rigid.
      b = std::max(soft.biasRate * (s + ctx.slop), -ctx.pushout);
      softRows |= 1u << k;
      rigid = false;
    }
    bias[k] = b;
    vn[k] = g[0] + m.alpha[k] * g[1] + m.beta[k] * g[2];
    speculative += b > 0.0;
    idle &= m.impulse[k] == 0.0 && vn[k] + bias[k] >= 0.0;
  }
  // Restitution answers the fastest approach before an impulse: the substep of impact
  // closes faster than the step's start did (by up to g dt at 60 Hz: 4 % of a 1 m drop).
  if (useBias && m.restitution != 0.0)
    for (int k = 0; k < N; ++k) m.approach[k] = std::min(m.approach[k], vn[k]);
  if (idle) return false;  // nothing pushes and nothing closes faster than allowed
  const bool block = moves == Moves::Both ? m.block : m.shockBlock;
  if (rigid && !m.direct && block && (speculative == 0 || speculative == N) &&
      solveNormalBlock<N>(m, A, B, g, bias, moves))
    return true;
  // Fewer points, or a guess that failed: the points' own coupling, exactly or by sweeps.
  const bool both = moves == Moves::Both;
  const double(*K)[4] = pointCouplings<N>(m, both);
  const bool exact = rigid && !m.direct && solveNormalActive<N>(m, K, vn, bias, delta);
  if (!exact) {
    const double* mass = both ? m.pointMass : m.shockPointMass;
    double massScale[4], impulseScale[4];
    for (int k = 0; k < N; ++k) {
      const bool softRow = softRows & (1u << k);
      massScale[k] = softRow ? soft.massScale : 1.0;
      impulseScale[k] = softRow ? soft.impulseScale : 0.0;
    }
    const int sweeps = N > 1 ? ctx.manifoldSweeps : 1;
    const Sweep sweep{K, vn, bias, mass, massScale, impulseScale, m.impulse};
    gaussSeidel<N>(sweep, sweeps, delta);
  }
  // Apply the point impulses as one: their three basis sums.
  double L[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < N; ++k) {
    m.impulse[k] += delta[k];
    m.maxImpulse[k] = std::max(m.maxImpulse[k], delta[k]);
    L[0] += delta[k], L[1] += m.alpha[k] * delta[k], L[2] += m.beta[k] * delta[k];
  }
  applyBasis(m, A, B, L, moves);
  return true;
}

// The point count as a constant: every per-point loop of the solve unrolls. True if it
// applied an impulse (an idle manifold changes nothing).
bool solveNormal(SolverManifold& m, SolverBody& A, SolverBody& B, const SolveContext& ctx,
                 bool useBias, Moves moves) {
  switch (m.count) {
    case 1:
      return solveNormalN<1>(m, A, B, ctx, useBias, moves);
    case 2:
      return solveNormalN<2>(m, A, B, ctx, useBias, moves);
    case 3:
      return solveNormalN<3>(m, A, B, ctx, useBias, moves);
    default:
      return solveNormalN<4>(m, A, B, ctx, useBias, moves);
  }
}

// Last step's impulses applied again, all rows of the manifold at once: one linear impulse
// (normal and tangents) and one angular change per body.
void warmStartManifold(const SolverManifold& m, SolverBody& A, SolverBody& B) {
  double L[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < m.count; ++k)
    L[0] += m.impulse[k], L[1] += m.alpha[k] * m.impulse[k], L[2] += m.beta[k] * m.impulse[k];
  Vec3 linear = L[0] * m.normal;
  Vec3 dwA = L[0] * m.dwA + L[1] * m.spinA[0] + L[2] * m.spinA[1];
  Vec3 dwB = L[0] * m.dwB + L[1] * m.spinB[0] + L[2] * m.spinB[1];
  for (const SolverRow& r : m.friction) {
    linear += r.impulse * r.lin;
    dwA += r.impulse * r.dwA, dwB += r.impulse * r.dwB;
  }
  A.v -= A.invMass * linear, A.w -= dwA;
  B.v += B.invMass * linear, B.w += dwB;
}

// The shock pass's rows, where only one body moves: the basis coupling, the friction masses
// and the patch inverse, prepared the first time a shock pass solves the manifold (many
// manifolds of a pile never meet one with rows ready).
void prepareShockRows(SolverManifold& m, const SolverBody& A, const SolverBody& B, Moves moves) {
  basisCoupling(m, A, B, moves, m.shockBasisK);
  m.shockCouplingReady = false;
  for (int r = 0; r < 3; ++r) m.shockFrictionMass[r] = rowMass(A, B, m.friction[r], moves);
  m.shockBlock = m.block && invertBlock(m.shockBasisK, m.shockBlockInv);
  m.shockReady = true;
}

// How fast a body's surface at a manifold moves across its normal: sliding, plus turning.
inline double acrossSpeed(const SolverBody& b, const Vec3& normal, double reach) {
  return (b.v - b.v.dot(normal) * normal).norm() + reach * b.w.norm();
}

// Which bodies a shock pass moves: the body farther from the ground only, unless
// - the nearer one presses into it (it tips up under a load it should carry, as a Jenga block
//   pushed past its support's edge under the layers above): then both, or the upper bodies
//   would give way;
// - the nearer one slides or turns across the contact faster than a resting body can
//   (ctx.supportSpeed): then both. Held still while it moves with the tower, a support gave
//   the bodies above velocity its held reaction never took back, and collapsing towers gained
//   energy (docs/dynamics.md). A stack settling moves along the normal, and a Jenga block
//   pushed out at a hand's pace (3 cm/s) slower than that: they keep their shock passes.
inline Moves shockMoves(const SolverManifold& m, const std::vector<SolverBody>& bodies,
                        const SolveContext& ctx) {
  const Moves moves = static_cast<Moves>(m.shockMoves);
  if (moves == Moves::Both) return moves;
  const SolverBody &A = bodies[m.a], &B = bodies[m.b];
  const SolverBody& support = moves == Moves::OnlyB ? A : B;
  if (acrossSpeed(support, m.normal, moves == Moves::OnlyB ? m.reachA : m.reachB) >
      ctx.supportSpeed)
    return Moves::Both;
  const double pressing = moves == Moves::OnlyB ? m.normal.dot(A.v) + m.armA.dot(A.w)
                                                : -(m.normal.dot(B.v) + m.armB.dot(B.w));
  return pressing > ctx.breakVelocity ? Moves::Both : moves;
}

// Friction first, against the current normal impulse; non-penetration last, so it has the
// final word (as Jolt orders them; measured: normal-first lets tall stacks drift). A new
// contact (no warm start) solves its normal before and after its friction; static friction
// may break only in a relax pass of a warm contact.
inline void solveManifold(SolverManifold& m, std::vector<SolverBody>& bodies,
                          const SolveContext& ctx, bool useBias, Moves moves = Moves::Both) {
  SolverBody& A = bodies[m.a];
  SolverBody& B = bodies[m.b];
  const bool mayBreak = !useBias && m.warm;
  if (moves != Moves::Both && !m.shockReady) prepareShockRows(m, A, B, moves);
  // A new contact's normal goes first too, so its friction is not judged against a zero
  // normal impulse (the second solve takes out the tipping that friction at the patch adds).
  // If neither changes anything (a gap that stays open), the second solve would find the same.
  if (!m.warm) {
    const bool pushed = solveNormal(m, A, B, ctx, useBias, moves);
    if (solveFriction(m, A, B, ctx, useBias, moves, mayBreak) || pushed)
      solveNormal(m, A, B, ctx, useBias, moves);
    return;
  }
  solveFriction(m, A, B, ctx, useBias, moves, mayBreak);
  solveNormal(m, A, B, ctx, useBias, moves);
}

// Coupling of two normal rows through the bodies they share: J_i M^-1 J_j^T.
double coupling(const SolverManifold& mi, const SolverRow& ri, const SolverManifold& mj,
                const SolverRow& rj, const std::vector<SolverBody>& bodies) {
  double k = 0.0;
  for (int x : {mi.a, mi.b}) {
    if (x != mj.a && x != mj.b) continue;
    const bool iB = x == mi.b, jB = x == mj.b;
    const double sign = iB == jB ? 1.0 : -1.0;
    k += sign * (bodies[x].invMass * ri.lin.dot(rj.lin) +
                 (iB ? ri.angB : ri.angA).dot(jB ? rj.dwB : rj.dwA));
  }
  return k;
}

// The normal impulses of one small island solved together, for islands of very unequal
// masses (see computeLevels): all its rows at once with their coupling K, by an active set
// (a row whose impulse would pull is let go, a let-go row that would close is taken back, and
// the rest solved again). Friction stays with Gauss-Seidel. If the active set does not
// settle, the Gauss-Seidel result stands.
void solveIslandNormals(std::vector<SolverManifold>& manifolds, std::vector<SolverBody>& bodies,
                        const int* list, const SolveContext& ctx, bool useBias) {
  using MatN = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kDirectRows, kDirectRows>;
  using VecN = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kDirectRows, 1>;
  struct Row {
    SolverManifold* m;
    int point;
    SolverRow row;  // written out
  };
  std::array<Row, kDirectRows> rows;
  int n = 0;
  for (const int* i = list; *i >= 0; ++i)
    for (int k = 0; k < manifolds[*i].count; ++k)
      rows[n++] = {&manifolds[*i], k, pointRow(manifolds[*i], k)};
  MatN K(n, n);
  VecN rhs(n), lambda(n), bias(n);
  for (int i = 0; i < n; ++i) {
    const SolverManifold& m = *rows[i].m;
    const SolverRow& r = rows[i].row;
    const SolverBody &A = bodies[m.a], &B = bodies[m.b];
    for (int j = 0; j < n; ++j) K(i, j) = coupling(m, r, *rows[j].m, rows[j].row, bodies);
    const Softness& soft = ctx.onWorld(m) ? ctx.staticSoft : ctx.soft;
    const double sep = m.separation[rows[i].point] + r.lin.dot(B.dp - A.dp) + r.angB.dot(B.dtheta) -
                       r.angA.dot(A.dtheta);
    double b = 0.0, massScale = 1.0, impulseScale = 0.0;
    if (sep > 0.0) {
      b = sep * ctx.invH;
    } else if (useBias && sep < -ctx.slop) {
      b = std::max(soft.biasRate * (sep + ctx.slop), -ctx.pushout);
      massScale = soft.massScale, impulseScale = soft.impulseScale;
    }
    lambda[i] = r.impulse;
    bias[i] = b;
    // Soft rows as in solveNormal: dl k / s + (i k / s) l = -(v + b).
    const double kii = K(i, i);
    rhs[i] = -(rowVelocity(A, B, r) + b) - impulseScale * kii / massScale * lambda[i];
    K(i, i) = kii / massScale;
  }
  std::array<bool, kDirectRows> active;
  active.fill(true);
  VecN delta = VecN::Zero(n);
  for (int round = 0; round < 8; ++round) {
    std::array<int, kDirectRows> idx;
    int na = 0;
    for (int i = 0; i < n; ++i)
      if (active[i]) idx[na++] = i;
    for (int i = 0; i < n; ++i) delta[i] = active[i] ? 0.0 : -lambda[i];  // let go: no impulse
    if (na > 0) {
      MatN Ka(na, na);
      VecN ra(na);
      double trace = 0.0;
      for (int x = 0; x < na; ++x) {
        ra[x] = rhs[idx[x]];
        for (int j = 0; j < n; ++j)
          if (!active[j]) ra[x] -= K(idx[x], j) * delta[j];
        for (int y = 0; y < na; ++y) Ka(x, y) = K(idx[x], idx[y]);
        trace += Ka(x, x);
      }
      // A face's four points constrain only three motions: the tiny regularisation picks the
      // even split among the equivalent impulse sets.
      Ka.diagonal().array() += 1e-6 * trace / na;
      const VecN da = Ka.ldlt().solve(ra);
      if (!da.allFinite()) return;
      for (int x = 0; x < na; ++x) delta[idx[x]] = da[x];
    }
    bool changed = false;
    for (int i = 0; i < n; ++i)
      if (active[i] && lambda[i] + delta[i] < 0.0) active[i] = false, changed = true;
    // A let-go row must not end up closing faster than its bias allows: take it back if so.
    for (int i = 0; i < n && !changed; ++i) {
      if (active[i]) continue;
      double closing = rhs[i];
      for (int j = 0; j < n; ++j) closing -= K(i, j) * delta[j];
      if (closing > 1e-9) active[i] = true, changed = true;
    }
    if (changed) continue;
    for (int i = 0; i < n; ++i) {
      SolverManifold& m = *rows[i].m;
      const int k = rows[i].point;
      m.impulse[k] = lambda[i] + delta[i];
      m.maxImpulse[k] = std::max(m.maxImpulse[k], delta[i]);
      applyRow(bodies[m.a], bodies[m.b], rows[i].row, delta[i]);
    }
    return;
  }
}

void undoLoadStep(const detail::LoadStep& u, std::vector<SolverManifold>& manifolds,
                  std::vector<SolverBody>& bodies) {
  SolverManifold& m = manifolds[u.manifold];
  std::copy(u.impulse, u.impulse + 4, m.impulse);
  std::copy(u.maxImpulse, u.maxImpulse + 4, m.maxImpulse);
  for (int r = 0; r < 3; ++r) m.friction[r].impulse = u.friction[r];
  m.sliding = u.sliding;
  SolverBody &upper = bodies[u.upper], &lower = bodies[u.lower];
  upper.v = u.v, upper.w = u.w, upper.heldV = u.heldV, upper.heldW = u.heldW;
  lower.heldV = u.lowerHeldV, lower.heldW = u.lowerHeldW;
}

// One hand-down of the load pass (see solve): the upper body of manifold m takes back its held
// reactions and m, with the lower body held still, stops it. Kept (true, with what it changed
// in `undo`) if the body ends as it was, within a thousandth of what it took back; else undone.
bool handLoadDown(int index, std::vector<SolverManifold>& manifolds,
                  std::vector<SolverBody>& bodies, const SolveContext& ctx, Moves moves,
                  detail::LoadStep& undo) {
  SolverManifold& m = manifolds[index];
  undo.manifold = index;
  undo.upper = moves == Moves::OnlyB ? m.b : m.a;
  undo.lower = moves == Moves::OnlyB ? m.a : m.b;
  SolverBody &upper = bodies[undo.upper], &lower = bodies[undo.lower];
  const double reach = moves == Moves::OnlyB ? m.reachB : m.reachA;
  const double taken = upper.heldV.norm() + reach * upper.heldW.norm();
  std::copy(m.impulse, m.impulse + 4, undo.impulse);
  std::copy(m.maxImpulse, m.maxImpulse + 4, undo.maxImpulse);
  for (int r = 0; r < 3; ++r) undo.friction[r] = m.friction[r].impulse;
  undo.sliding = m.sliding;
  undo.v = upper.v, undo.w = upper.w, undo.heldV = upper.heldV, undo.heldW = upper.heldW;
  undo.lowerHeldV = lower.heldV, undo.lowerHeldW = lower.heldW;
  if (!(taken > 0.0)) return true;  // nothing held: nothing to hand down
  // Only a body at rest on its support: in a toppling or sliding island the loads are not
  // the weights above, and handing them down fed the next warm start impulses it had to undo.
  const double relative = (upper.v - lower.v).norm() + reach * (upper.w - lower.w).norm();
  if (relative > ctx.restingSpeed) return false;
  upper.v += upper.heldV, upper.w += upper.heldW;
  upper.heldV.setZero(), upper.heldW.setZero();
  solveManifold(m, bodies, ctx, false, moves);
  const double moved = (upper.v - undo.v).norm() + reach * (upper.w - undo.w).norm();
  if (moved <= 1e-3 * taken) return true;
  undoLoadStep(undo, manifolds, bodies);
  return false;
}

double combineFriction(double a, double b) {
  return std::sqrt(a * b);
}

}  // namespace

template <class Each>
void World::Impl::forManifolds(int region, const Each& each) {
  const int begin = region == 0 ? 0 : manifoldEnd[region - 1];
  const int end =
      region == kAcross ? static_cast<int>(solverManifolds.size()) : manifoldEnd[region];
  for (int i = begin; i < end; ++i) each(i);
}

void World::Impl::solve(double dt) {
  const int substeps = substepsFor(dt);
  const double h = dt / substeps;

  setUpSolverBodies();
  prepareJoints();
  frameJoints();
  prepareContacts();
  computeLevels();
  // The shock order within each region (ground up), then across.
  shockEnd[0] = static_cast<int>(
      std::stable_partition(shockOrder.begin(), shockOrder.end(),
                            [&](int i) { return solverManifolds[i].region == 0; }) -
      shockOrder.begin());
  shockEnd[1] = static_cast<int>(
      std::stable_partition(shockOrder.begin() + shockEnd[0], shockOrder.end(),
                            [&](int i) { return solverManifolds[i].region == 1; }) -
      shockOrder.begin());
  auto most = [](const std::vector<int>& v) {
    return v.empty() ? 0 : *std::max_element(v.begin(), v.end());
  };
  const int maxRelaxPasses = most(relaxPasses), maxFirstPasses = most(firstSubstepPasses);

  SolveContext ctx;
  ctx.invH = 1.0 / h, ctx.slop = def.linearSlop, ctx.pushout = def.maxPushoutVelocity;
  ctx.breakVelocity = 0.1 * def.stickVelocity;
  ctx.restingSpeed = def.sleepLinearVelocity;
  // Resting, plus what gravity adds in a step before the contacts take it out (an incline).
  ctx.supportSpeed = def.sleepLinearVelocity + def.gravity.norm() * dt;
  ctx.touching = def.positionSlop;
  const double hertz = std::min(def.contactHertz, 0.25 / h);
  ctx.soft = makeSoft(hertz, def.contactDampingRatio, h);
  ctx.staticSoft = makeSoft(2.0 * hertz, def.contactDampingRatio, h);
  ctx.anchorSoft = makeSoft(2.0 * hertz, def.contactDampingRatio, h);
  ctx.worldTwin = worldTwin;

  auto solveDirectIslands = [&](const SolveContext& c, bool useBias) {
    for (size_t i = 0; i < directManifolds.size(); ++i) {
      solveIslandNormals(solverManifolds, solverBodies, &directManifolds[i], c, useBias);
      while (directManifolds[i] >= 0) ++i;
    }
  };

  // A manifold whose rows wait (prepareRows) is solved once the bounds no longer show it idle;
  // until then solving it would change nothing.
  auto ready = [&](size_t i, bool useBias) {
    SolverManifold& m = solverManifolds[i];
    if (m.rowsReady) return true;
    const SolverBody &A = solverBodies[m.a], &B = solverBodies[m.b];
    if (idleByBounds(m, A, B, ctx, useBias, m.normal.dot(B.v - A.v), m.normal.dot(B.dp - A.dp)))
      return false;
    prepareRows(m);
    prepareShock(i);
    return true;
  };

  // Region r's bodies, manifolds and shock order (r = kAcross: the manifolds across the cut).
  const int manifoldCount = static_cast<int>(solverManifolds.size());
  auto manifoldsOf = [&](int r, const auto& each) { forManifolds(r, each); };
  auto shocksOf = [&](int r, const auto& each) {
    const int begin = r == 0 ? 0 : shockEnd[r - 1];
    const int end = r == kAcross ? manifoldCount : shockEnd[r];
    for (int k = begin; k < end; ++k) each(shockOrder[k]);
  };
  auto warmStartAt = [&](int i) {  // a manifold without rows holds no impulse
    SolverManifold& m = solverManifolds[i];
    if (m.rowsReady) warmStartManifold(m, solverBodies[m.a], solverBodies[m.b]);
  };

  const bool withJoints = !solvedJoints.empty();
  for (int sub = 0; sub < substeps; ++sub) {
    inBothRegions([&](int r) {
      for (int k : bodiesOf(r)) {
        SolverBody& b = solverBodies[k + 1];
        // What the contacts did last substep, for this one's warm start (warmStart).
        if (sub > 0) b.heldV += b.v - b.startV, b.heldW += b.w - b.startW;
        if (withJoints) {  // not what the joints did: they warm start themselves (joints.cpp)
          if (sub > 0) b.heldV -= b.jointV, b.heldW -= b.jointW;
          b.jointV.setZero(), b.jointW.setZero();
        }
        integrateVelocity(k, h);
        warmStart(b, sub);
      }
    });
    if (sub == 0) manifoldsOf(kAcross, warmStartAt);
    warmStartJoints();
    auto biasedPass = [&](int r) {
      manifoldsOf(r, [&](int i) {
        if (ready(i, true)) solveManifold(solverManifolds[i], solverBodies, ctx, true);
      });
    };
    inBothRegions([&](int r) {
      if (sub == 0) manifoldsOf(r, warmStartAt);
      biasedPass(r);
    });
    biasedPass(kAcross);
    solveDirectIslands(ctx, true);
    solveJoints(h, true);  // (after both regions: the joints' bodies may be in either)
    // Relax passes; each island runs its own number of them (computeLevels), and its last
    // one is a shock propagation pass (Guendelman et al. 2003): from the ground up, each
    // contact moves only the body farther from the ground, so a stack's support reaches its
    // top within one pass instead of diffusing slowly.
    const std::vector<int>& passes = sub == 0 ? firstSubstepPasses : relaxPasses;
    auto relax = [&](int r) {
      for (int pass = 0; pass < (sub == 0 ? maxFirstPasses : maxRelaxPasses); ++pass) {
        manifoldsOf(r, [&](int i) {
          if (passes[i] > pass + 1 && ready(i, false))
            solveManifold(solverManifolds[i], solverBodies, ctx, false);
        });
        shocksOf(r, [&](int i) {
          if (passes[i] != pass + 1 || !ready(i, false)) return;
          SolverManifold& m = solverManifolds[i];
          solveManifold(m, solverBodies, ctx, false, shockMoves(m, solverBodies, ctx));
        });
      }
    };
    inBothRegions([&](int r) {
      for (int k : bodiesOf(r)) integratePosition(k, h);
      relax(r);
    });
    relax(kAcross);
    frameJoints();  // the positions moved; the next substep's warm start shares this frame
    solveJoints(h, false);
    // The load pass, from the top down: a body resting on one support alone takes back the
    // reactions the shock passes held from it (the loads of the bodies above), and where that
    // support stops it again as it was, the impulses carry the load down to the ground in
    // one pass instead of learning it over steps. Only chains of such bodies that end on a
    // static one, and only whole islands: where one support cannot carry its load (a body
    // would tip or slide), the island's hand-downs are undone, as a load left half way
    // down would be thrown at one body by the next warm start.
    loadLog.clear();
    for (size_t k = 0; k < soleSupports.size(); ++k) {
      const int i = soleSupports[k];
      if (!ready(i, false) || islandRefused[soleSupportIslands[k]]) continue;
      const Moves moves = shockMoves(solverManifolds[i], solverBodies, ctx);
      if (moves == Moves::Both) continue;
      detail::LoadStep& undo = loadLog.emplace_back();
      undo.island = soleSupportIslands[k];
      if (!handLoadDown(i, solverManifolds, solverBodies, ctx, moves, undo)) {
        islandRefused[undo.island] = 1;
        loadLog.pop_back();
      }
    }
    for (auto it = loadLog.rbegin(); it != loadLog.rend(); ++it)
      if (islandRefused[it->island]) undoLoadStep(*it, solverManifolds, solverBodies);
    for (int island : soleSupportIslands) islandRefused[island] = 0;
    solveDirectIslands(ctx, false);
  }

  // Restitution, the position projection (its passes from the ground up), the impulses kept
  // for the next step, and the bodies written back.
  auto restitute = [&](int i) { applyRestitution(solverManifolds[i]); };
  inBothRegions([&](int r) { manifoldsOf(r, restitute); });
  manifoldsOf(kAcross, restitute);
  auto project = [&](int i) { projectPosition(solverManifolds[i]); };
  for (int it = 0; it < def.positionIterations; ++it) {
    inBothRegions([&](int r) { shocksOf(r, project); });
    shocksOf(kAcross, project);
  }
  auto store = [&](int i) { storeImpulses(solverManifolds[i]); };
  inBothRegions([&](int r) {
    manifoldsOf(r, store);
    if (r == 0) manifoldsOf(kAcross, store);
    for (int k : bodiesOf(r)) {
      SolverBody& s = solverBodies[k + 1];
      if (!s.correction.isZero()) s.dq = integrateRotation(s.dq, s.correction, 1.0);
      Body& b = bodies[awakeBodies[k]];
      b.v = s.v, b.w = s.w;
      b.com += s.dp;
      b.pose.q = (s.dq * b.pose.q).normalized();
      b.pose.p = b.com - b.pose.q * b.localCom;
      refreshBounds(awakeBodies[k]);
    }
  });
}

// The warm start: the accumulated impulses applied again. A substep's impulses add up to the
// accumulated impulses it ends with, which are what the next substep applies again; so from
// the second substep on, each body gets the velocity change the contacts gave it in the
// substep before (kept in heldV, heldW) instead of a pass over every manifold's rows, which
// was 8 % of a 1000-box pile's step, bound by memory. The same up to rounding. (The first
// substep applies the manifolds' impulses: solve.)
void World::Impl::warmStart(SolverBody& b, int substep) {
  b.startV = b.v, b.startW = b.w;
  if (substep > 0) b.v += b.heldV, b.w += b.heldW;
  b.heldV.setZero(), b.heldW.setZero();
}

// The solver bodies: index 0 is the immovable world, then the moving bodies in their regions
// (assignRegions: region 0's first), each region's set up by the thread that will solve them,
// so their cache lines stay with it. Region 1 gets its own immovable world, last: the bodies
// resting on the ground in both regions would otherwise write (zeros) to one world body from
// both threads.
void World::Impl::setUpSolverBodies() {
  for (uint32_t slot : awakeBodies) solverIndexOf[slot] = 0;  // last step's, one by one
  solverIndexOf.resize(bodies.size(), 0);
  awakeBodies.assign(regionSlots.begin(), regionSlots.end());
  const int n = static_cast<int>(awakeBodies.size());
  regionBodyEnd = static_cast<int>(regionSlotEnd);
  stats.solveRegions = regionCount;
  solverRegion.assign(static_cast<size_t>(n + 1), kNoRegion);
  for (int k = 0; k < n; ++k) {
    solverIndexOf[awakeBodies[k]] = k + 1;
    solverRegion[k + 1] = k < regionBodyEnd ? 0 : 1;
  }
  worldTwin = regionCount == 2 ? n + 1 : 0;
  if (regionCount == 2) solverRegion.push_back(kNoRegion);
  // (Kept from the last step, not built anew: each is set again below.)
  solverBodies.resize(solverRegion.size());
  solverBodies[0] = SolverBody{};
  if (worldTwin) solverBodies[worldTwin] = SolverBody{};
  inBothRegions([&](int region) {
    for (int k : bodiesOf(region)) {
      const Body& b = bodies[awakeBodies[k]];
      SolverBody& s = solverBodies[k + 1];
      s = SolverBody{};
      s.v = b.v, s.w = b.w;
      s.invMass = b.invMass;
      s.invI = b.isDynamic() ? b.invInertiaWorld() : Mat3::Zero();
    }
  });
}

// Region r's awake bodies (solver index - 1).
detail::IndexRange World::Impl::bodiesOf(int region) const {
  const int n = static_cast<int>(awakeBodies.size());
  return region == 0 ? detail::IndexRange{0, regionBodyEnd} : detail::IndexRange{regionBodyEnd, n};
}

void World::Impl::prepareContacts() {
  // The contacts with a body that moves take part, region 0's first, then region 1's, then
  // those across the cut (each group in key order); each is prepared on its own.
  // The list keeps its manifolds from the last step (1.7 KB each, not built anew): each field
  // is set again by prepareManifold.
  // (The kept run holds none: its bodies do not move.)
  static thread_local std::vector<std::pair<uint8_t, int>> byRegion[3];  // run, index
  for (auto& list : byRegion) list.clear();
  for (uint8_t run = 0; run < 2; ++run) {
    const std::vector<uint64_t>& keys = contacts.run[run].pairKeys;  // (not the manifolds)
    for (size_t ci = 0; ci < keys.size(); ++ci) {
      const uint32_t bodyA = detail::firstOfPair(keys[ci]), bodyB = detail::secondOfPair(keys[ci]);
      const int a = solverIndexOf[bodyA], b = solverIndexOf[bodyB];
      if (a == 0 && b == 0) continue;
      if (!bodies[bodyA].isDynamic() && !bodies[bodyB].isDynamic()) continue;
      const uint8_t ra = solverRegion[a], rb = solverRegion[b];
      const uint8_t region = ra == kNoRegion ? rb : rb == kNoRegion || ra == rb ? ra : kAcross;
      byRegion[region].emplace_back(run, static_cast<int>(ci));
    }
  }
  // Room for kManifoldsPerBody a moving body up front, as a landing pile's list would otherwise
  // grow a few times, each time copying its 1.7 KB manifolds into fresh pages (3 % of the
  // 1000-box pile's two-thread step). Capacity not yet used costs address space, not memory.
  const size_t count = byRegion[0].size() + byRegion[1].size() + byRegion[2].size();
  if (count > solverManifolds.capacity())
    solverManifolds.reserve(std::max(2 * count, kManifoldsPerBody * awakeBodies.size()));
  solverManifolds.resize(count);
  links.resize(solverManifolds.size());
  manifoldEnd[0] = static_cast<int>(byRegion[0].size());
  manifoldEnd[1] = manifoldEnd[0] + static_cast<int>(byRegion[1].size());
  // Each region's thread prepares the manifolds it solves (the first one those across too).
  const auto* lists = byRegion;  // this thread's, for the helper too
  auto prepare = [&](uint8_t region) {
    int i = region == 0 ? 0 : manifoldEnd[region - 1];
    for (const auto& [run, ci] : lists[region]) {
      SolverManifold& m = solverManifolds[i++];
      m.sourceRun = run, m.source = ci, m.region = region;
      prepareManifold(m);
      links[static_cast<size_t>(i - 1)] = {m.a,
                                           m.b,
                                           m.warm || m.minSeparation < def.positionSlop,
                                           !m.warm && m.separation[0] <= 0.0,
                                           static_cast<uint8_t>(m.count),
                                           0};
    }
  };
  inBothRegions([&](int region) {
    prepare(static_cast<uint8_t>(region));
    if (region == 0) prepare(kAcross);
  });
  int points = 0;
  for (const detail::ManifoldLink& l : links) points += l.count;
  constraintCount = points;
  stats.manifolds = static_cast<int>(solverManifolds.size());
  stats.contactPoints = points;
  stats.awakeBodies = static_cast<int>(awakeBodies.size());
}

void World::Impl::prepareManifold(SolverManifold& m) {
  ContactManifold& c = sourceOf(m);
  const Body &A = bodies[c.bodyA], &B = bodies[c.bodyB];
  m.a = solverIndexOf[c.bodyA], m.b = solverIndexOf[c.bodyB];
  if (m.region == 1) m.a = m.a == 0 ? worldTwin : m.a, m.b = m.b == 0 ? worldTwin : m.b;
  const Vec3 n = c.m.normal;
  m.normal = n;
  m.staticFriction = combineFriction(A.material.staticFriction, B.material.staticFriction);
  m.dynamicFriction = combineFriction(A.material.dynamicFriction, B.material.dynamicFriction);
  m.restitution = std::max(A.material.restitution, B.material.restitution);
  m.bouncy = m.restitution != 0.0;
  m.count = c.m.pointCount;
  m.anchored = true, m.block = false, m.direct = false;
  m.warm = false;
  double reachA2 = 0.0, reachB2 = 0.0;
  m.minSeparation = std::numeric_limits<double>::infinity();
  m.patchCentre = Vec3::Zero();
  for (int k = 0; k < m.count; ++k) {
    const ContactPoint& cp = c.m.points[k];
    m.impulse[k] = c.state[k].normalImpulse;
    m.maxImpulse[k] = 0.0;
    m.warm |= m.impulse[k] != 0.0;
    m.separation[k] = cp.separation;
    m.minSeparation = std::min(m.minSeparation, cp.separation);
    reachA2 = std::max(reachA2, (cp.position - A.com).cross(n).squaredNorm());
    reachB2 = std::max(reachB2, (cp.position - B.com).cross(n).squaredNorm());
    m.patchCentre += cp.position;
  }
  m.reachA = std::sqrt(reachA2), m.reachB = std::sqrt(reachB2);
  m.patchCentre /= m.count;
  const Vec3& centre = m.patchCentre;
  // Patch friction at the centre of the points.
  tangentBasis(n, m.friction[0].lin, m.friction[1].lin);
  const Vec3 &t1 = m.friction[0].lin, &t2 = m.friction[1].lin;
  bool heldFriction = false;
  for (int r = 0; r < 3; ++r) {
    m.friction[r].impulse = c.friction[r];
    heldFriction |= c.friction[r] != 0.0;
  }
  // The anchor: kept while the patch sticks and stays within the slop of it, else reset to
  // the patch centre (a new or sliding patch starts from where it is).
  if (c.anchored && !c.sliding) {
    const Vec3 drift = B.pose.apply(c.anchorB) - A.pose.apply(c.anchorA);
    m.anchorError[0] = drift.dot(t1), m.anchorError[1] = drift.dot(t2);
    // (Squares: std::hypot guards against overflow, which a drift checked against a slop cannot
    // reach, at about 45 cycles a manifold.)
    const double e0 = m.anchorError[0], e1 = m.anchorError[1];
    if (e0 * e0 + e1 * e1 > def.linearSlop * def.linearSlop) c.anchored = false;
  }
  if (!c.anchored || c.sliding) {
    c.anchorA = A.pose.inverse().apply(centre), c.anchorB = B.pose.inverse().apply(centre);
    c.anchored = true;
    m.anchorError[0] = m.anchorError[1] = 0.0;
  }
  // Static friction while the patch rests, kinetic once it moves along the surface.
  const Vec3 rA = centre - A.com, rB = centre - B.com;
  const Vec3 dv = (B.v + B.w.cross(rB)) - (A.v + A.w.cross(rA));
  m.sliding = (dv - dv.dot(n) * n).norm() > def.stickVelocity;
  // A gap that held no impulse may never push this step (a third of a pile's manifolds): its
  // rows wait until a solve cannot rule that out from the bounds (prepareRows).
  m.rowsReady = false;
  if (m.warm || heldFriction || !(m.minSeparation > 0.0) || m.restitution != 0.0) prepareRows(m);
}

// The solver rows of a manifold: the normal basis and its coupling, the points' place in it,
// the patch friction rows and the exact patch solve. The same whenever it runs in the step: it
// reads only the bodies as they were at the step's start.
void World::Impl::prepareRows(SolverManifold& m) {
  const ContactManifold& c = sourceOf(m);
  const Body &A = bodies[c.bodyA], &B = bodies[c.bodyB];
  const SolverBody &sa = solverBodies[m.a], &sb = solverBodies[m.b];
  const Vec3& n = m.normal;
  const Vec3& centre = m.patchCentre;
  const Vec3 t1 = m.friction[0].lin, t2 = m.friction[1].lin;  // set by prepareManifold
  const Vec3 rA = centre - A.com, rB = centre - B.com;
  m.armA = rA.cross(n), m.armB = rB.cross(n);
  m.dwA = sa.invI * m.armA, m.dwB = sb.invI * m.armB;
  m.spinA[0] = sa.invI * t1, m.spinA[1] = sa.invI * t2;
  m.spinB[0] = sb.invI * t1, m.spinB[1] = sb.invI * t2;
  basisCoupling(m, sa, sb, Moves::Both, m.basisK);
  m.twistRadius = 0.0;
  for (int k = 0; k < m.count; ++k) {
    const Vec3 d = c.m.points[k].position - centre;
    const Vec3 arm = d.cross(n);
    m.alpha[k] = arm.dot(t1), m.beta[k] = arm.dot(t2);
    m.twistRadius += d.norm();
  }
  m.twistRadius /= m.count;
  for (int k = 0; k < m.count; ++k) {  // 1 / K_kk, K_kk = c_k . Kb c_k
    const double(&kb)[3][3] = m.basisK;
    const double a = m.alpha[k], b = m.beta[k];
    const double kk = kb[0][0] + 2.0 * (a * kb[0][1] + b * kb[0][2]) + a * a * kb[1][1] +
                      2.0 * a * b * kb[1][2] + b * b * kb[2][2];
    m.pointMass[k] = kk > 0.0 ? 1.0 / kk : 0.0;
  }
  m.couplingReady = m.shockCouplingReady = false;
  if (m.restitution != 0.0) {  // read only by bouncy manifolds: each point's approach speed
    const Vec3 spin = B.w - A.w;
    const double g0 = n.dot(B.v - A.v) + m.armB.dot(B.w) - m.armA.dot(A.w);
    const double g1 = t1.dot(spin), g2 = t2.dot(spin);
    for (int k = 0; k < m.count; ++k) m.approach[k] = g0 + m.alpha[k] * g1 + m.beta[k] * g2;
  }
  const double impulses[3] = {m.friction[0].impulse, m.friction[1].impulse, m.friction[2].impulse};
  m.friction[0] = makeRow(sa, sb, t1, rA.cross(t1), rB.cross(t1));
  m.friction[1] = makeRow(sa, sb, t2, rA.cross(t2), rB.cross(t2));
  m.friction[2] = makeRow(sa, sb, Vec3::Zero(), n, n);
  for (int r = 0; r < 3; ++r) m.friction[r].impulse = impulses[r];
  prepareBlock(m);
  m.rowsReady = true;
}

Vec3 detail::limitLength(const Vec3& v, double max) {
  if (!v.allFinite()) {
    Vec3 d = Vec3::Zero();
    for (int i = 0; i < 3; ++i) d[i] = std::isinf(v[i]) ? std::copysign(1.0, v[i]) : 0.0;
    return d.isZero() ? Vec3::Zero() : Vec3(d.normalized() * max);
  }
  const double length = v.norm();
  return length > max ? Vec3(v * (max / length)) : v;
}

Vec3 detail::tameLoad(const Vec3& x) {
  constexpr double kLargest = 1e100;
  if (!x.allFinite()) return limitLength(x, kLargest);
  const double m = x.lpNorm<Eigen::Infinity>();
  return m > kLargest ? Vec3(x * (kLargest / m)) : x;
}

void World::Impl::integrateVelocity(int k, double h) {
  const Body& b = bodies[awakeBodies[k]];
  SolverBody& s = solverBodies[k + 1];
  if (!b.isDynamic()) return;
  // Most bodies feel gravity only: the loads, the damping and the limits are skipped where
  // they would change nothing (adding a zero load, scaling by 1, a speed within the limit).
  s.v += h * b.loadAcceleration(def.gravity);
  if (!b.torque.isZero() || !b.angularAccel.isZero()) {
    const Mat3 R = (s.dq * b.pose.q).toRotationMatrix();
    s.w += h * (R * (b.invInertiaLocal * (R.transpose() * detail::tameLoad(b.torque))) +
                detail::tameLoad(b.angularAccel));
  }
  if (b.linearDamping != 0.0) s.v *= 1.0 / (1.0 + h * b.linearDamping);
  if (b.angularDamping != 0.0) s.w *= 1.0 / (1.0 + h * b.angularDamping);
  if (!(s.v.norm() <= def.maxLinearSpeed)) s.v = detail::limitLength(s.v, def.maxLinearSpeed);
  if (!(s.w.norm() <= def.maxAngularSpeed)) s.w = detail::limitLength(s.w, def.maxAngularSpeed);
}

// Positions and orientations advance with the substep's velocities. A body that is not
// isotropic turns as a free rigid body does over the substep, keeping its world angular
// momentum L exactly: the rotation is split into turns about its principal axes, each exact
// (x, y by h/2, z by h, y, x by h/2: symmetric, second order, with an energy error that stays
// bounded instead of drifting; the plain update w <- I(q1)^-1 I(q0) w lost 45 % of a spin's
// energy near the intermediate axis in 10 s). This is the gyroscopic effect, implicitly: |w|
// can never blow up at any spin rate (unlike an explicit w x Iw torque).
void World::Impl::integratePosition(int k, double h) {
  const Body& b = bodies[awakeBodies[k]];
  SolverBody& s = solverBodies[k + 1];
  s.dp += h * s.v;
  s.dtheta += h * s.w;
  s.turned = s.dtheta.norm();
  if (!b.isDynamic() || b.isotropic || s.w.isZero()) {
    s.dq = integrateRotation(s.dq, s.w, h);
    return;
  }
  // In the principal frame: momentum pi, orientation qp (world from principal).
  Quat qp = s.dq * b.pose.q * b.principalFrame;
  const Vec3 L = (s.dq * b.pose.q) * (b.inertiaLocal * ((s.dq * b.pose.q).conjugate() * s.w));
  Vec3 pi = qp.conjugate() * L;
  auto turn = [&](int axis, double t) {
    const double angle = t * pi[axis] / b.principalInertia[axis];
    const Quat r(Eigen::AngleAxisd(angle, Vec3::Unit(axis)));
    qp = qp * r;
    pi = r.conjugate() * pi;
  };
  turn(0, 0.5 * h), turn(1, 0.5 * h), turn(2, h), turn(1, 0.5 * h), turn(0, 0.5 * h);
  qp.normalize();
  s.dq = (qp * b.principalFrame.conjugate() * b.pose.q.conjugate()).normalized();
  const Vec3 before = s.w;
  s.w = qp * pi.cwiseQuotient(b.principalInertia);
  s.startW += s.w - before;  // a change the contacts did not make: not warm-started
}

// One pass on points that closed faster than the threshold and actually pushed.
void World::Impl::applyRestitution(SolverManifold& m) {
  if (m.restitution == 0.0) return;
  SolverBody &A = solverBodies[m.a], &B = solverBodies[m.b];
  for (int k = 0; k < m.count; ++k) {
    if (m.approach[k] > -def.restitutionThreshold || m.maxImpulse[k] == 0.0) continue;
    const SolverRow r = pointRow(m, k);
    const double vn = rowVelocity(A, B, r);
    const double total =
        std::max(m.impulse[k] - r.mass * (vn + m.restitution * m.approach[k]), 0.0);
    applyRow(A, B, r, total - m.impulse[k]);
    m.impulse[k] = total;
  }
}

// Position projection (non-linear Gauss-Seidel, as Box2D v2.4 and Jolt do): after the
// velocities are final, overlap beyond a small slop is removed by moving the bodies directly,
// a fraction per pass. It adds no velocity, so it cannot add energy, and it keeps stacks from
// sinking or leaning where a rigid velocity constraint alone would let them drift.
// A manifold's overlap goes in two parts: what all its points share, by a push at the patch
// centre that does not level the patch; then, point by point (which also levels it), what is
// deeper than the slop by more than kTiltSlop more. Point by point from the slop itself, a
// stack's contacts resting at the slop were levelled by turns that tilted the contacts above:
// a stack of 20 cubes of 15 mm (or 80 of 0.1 m) leaned more each second until it fell.
void World::Impl::projectPosition(SolverManifold& m) {
  const double slop = def.positionSlop, levelBeyond = slop + kTiltSlop * slop;
  SolverBody &A = solverBodies[m.a], &B = solverBodies[m.b];
  if (!m.rowsReady) {  // no point can be deeper than the bound (margin as in idleByBounds)
    const double gap = m.minSeparation + m.normal.dot(B.dp - A.dp) - m.reachA * A.dtheta.norm() -
                       m.reachB * B.dtheta.norm();
    if (gap > 1e-12 - slop) return;
    prepareRows(m);
  }
  // The basis rows' displacements since the step began; a push at point k moves them by
  // Kb c_k push, and the pushes reach the bodies as their three basis sums.
  const Vec3 turn = B.dtheta - A.dtheta;
  double x[3] = {m.normal.dot(B.dp - A.dp) + m.armB.dot(B.dtheta) - m.armA.dot(A.dtheta),
                 m.friction[0].lin.dot(turn), m.friction[1].lin.dot(turn)};
  auto separation = [&](int k) {
    return m.separation[k] + x[0] + m.alpha[k] * x[1] + m.beta[k] * x[2];
  };
  double P[3] = {0.0, 0.0, 0.0};
  double shared = std::numeric_limits<double>::infinity();
  for (int k = 0; k < m.count; ++k) shared = std::min(shared, -separation(k) - slop);
  if (shared > 0.0 && m.basisK[0][0] > 0.0) {
    P[0] = std::min(def.positionCorrection * shared, kMaxProjection) / m.basisK[0][0];
    for (int r = 0; r < 3; ++r) x[r] += m.basisK[r][0] * P[0];
  }
  for (int k = 0; k < m.count; ++k) {
    const double c[3] = {1.0, m.alpha[k], m.beta[k]};
    const double s = separation(k);
    if (s >= -levelBeyond) continue;
    const double push =
        m.pointMass[k] * std::min(-def.positionCorrection * (s + levelBeyond), kMaxProjection);
    for (int r = 0; r < 3; ++r) {
      P[r] += c[r] * push;
      x[r] += (m.basisK[r][0] + m.basisK[r][1] * c[1] + m.basisK[r][2] * c[2]) * push;
    }
  }
  if (P[0] == 0.0) return;
  const Vec3 rotA = P[0] * m.dwA + P[1] * m.spinA[0] + P[2] * m.spinA[1];
  const Vec3 rotB = P[0] * m.dwB + P[1] * m.spinB[0] + P[2] * m.spinB[1];
  A.dp -= (A.invMass * P[0]) * m.normal, A.dtheta -= rotA, A.correction -= rotA;
  B.dp += (B.invMass * P[0]) * m.normal, B.dtheta += rotB, B.correction += rotB;
}

void World::Impl::storeImpulses(const SolverManifold& m) {
  ContactManifold& c = sourceOf(m);
  for (int k = 0; k < m.count; ++k) c.state[k].normalImpulse = m.impulse[k];
  for (int r = 0; r < 3; ++r) c.friction[r] = m.friction[r].impulse;
  c.sliding = m.sliding;
  if (m.sliding) c.anchored = false;
}

// Contact levels for shock propagation: static and kinematic bodies are level 0, and every
// dynamic body is one more than the lowest level it touches (breadth first, in index order).
// Bodies not resting on anything keep a level above all others.
void World::Impl::computeLevels() {
  const int n = static_cast<int>(solverBodies.size());
  constexpr int kFree = 1 << 30;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kUnequalMass = 4.0;  // lightest vs heaviest body of an island
  levels.assign(n, kFree);
  adjacencyStart.assign(n + 1, 0);
  for (const detail::ManifoldLink& l : links) ++adjacencyStart[l.a + 1], ++adjacencyStart[l.b + 1];
  for (int i = 0; i < n; ++i) adjacencyStart[i + 1] += adjacencyStart[i];
  adjacency.resize(adjacencyStart[n]);
  fill.assign(adjacencyStart.begin(), adjacencyStart.end() - 1);
  for (int i = 0; i < static_cast<int>(links.size()); ++i) {
    adjacency[fill[links[i].a]++] = i;
    adjacency[fill[links[i].b]++] = i;
  }
  queue.clear();
  for (int i = 0; i < n; ++i)
    if (solverBodies[i].invMass == 0.0) levels[i] = 0, queue.push_back(i);
  // First through the contacts that bear a load (warm, or touching: within positionSlop, as
  // ctx.touching), then through the rest: a speculative contact across a gap (a block two
  // layers up, 15 mm away; a 3 mm poker chip two up, within linearSlop) must not put a body
  // level with the one it rests on, or the shock pass would not order them.
  // (A link bears a load when warm or within positionSlop: ManifoldLink::bearing.)
  auto spread = [&](bool all) {
    for (size_t q = 0; q < queue.size(); ++q) {
      const int body = queue[q];
      for (int e = adjacencyStart[body]; e < adjacencyStart[body + 1]; ++e) {
        const detail::ManifoldLink& l = links[adjacency[e]];
        if (!all && !l.bearing) continue;
        const int other = l.a == body ? l.b : l.a;
        if (levels[other] == kFree) levels[other] = levels[body] + 1, queue.push_back(other);
      }
    }
  };
  spread(false);
  bearing.assign(n, 0);
  for (int body : queue) bearing[body] = 1;
  // Bodies reached only across gaps (falling ones) take a level from a neighbour too.
  if (queue.size() < static_cast<size_t>(n)) spread(true);
  // Manifolds from the ground up (by their lower body's level; index order within a level):
  // a counting sort, as levels are small.
  const int count = static_cast<int>(links.size());
  int top = 0;
  for (int l : levels)
    if (l != kFree) top = std::max(top, l);
  auto lowLevel = [&](int i) {
    const int l = std::min(levels[links[i].a], levels[links[i].b]);
    return l == kFree ? top + 1 : l;
  };
  queue.assign(top + 3, 0);  // reused scratch: manifolds per level, then first slots
  for (int i = 0; i < count; ++i) ++queue[lowLevel(i) + 1];
  for (int l = 0; l <= top + 1; ++l) queue[l + 1] += queue[l];
  shockOrder.resize(count);
  for (int i = 0; i < count; ++i) shockOrder[queue[lowLevel(i)]++] = i;

  // Islands (union-find over the manifolds between moving bodies) and their heights. Support
  // must travel from the ground to the top of an island, and a Gauss-Seidel pass carries it
  // only so far: measured, before the load pass, stacks of up to 10 levels stood with one
  // relax pass, 20 needed about 5 and 50 about 18. So an island deeper than 12 levels gets
  // (2 (depth - 10) + 4) / 5 passes more than relaxIterations, up to maxRelaxIterations in all;
  // low piles pay nothing extra. The load pass now carries a column of cubes (80 stand with
  // no extra pass); narrow ones still need them (13 cubes of 15 mm, 1 kg, fall without), and
  // at 11 and 12 levels they stood the same with and without (cubes of 0.1 m and of 15 mm at
  // 10 g to 1 kg, measured 2026-12-05), where a 1000-box pile paid 7 % of its step for one.
  // The height counts only bodies reached through load-bearing contacts: a body still
  // falling onto the island carries no load down it.
  islandOf.resize(n);
  for (int i = 0; i < n; ++i) islandOf[i] = i;
  auto root = [&](int i) {
    while (islandOf[i] != i) i = islandOf[i] = islandOf[islandOf[i]];
    return i;
  };
  for (const detail::ManifoldLink& l : links) {
    if (levels[l.a] == 0 || levels[l.b] == 0) continue;  // static or kinematic
    const int ra = root(l.a), rb = root(l.b);
    if (ra != rb) islandOf[std::max(ra, rb)] = std::min(ra, rb);
  }
  islandDepth.assign(n, 0);
  islandLightest.assign(n, 0.0), islandHeaviest.assign(n, kInf);  // as inverse masses
  for (int i = 0; i < n; ++i) {
    const int r = root(i);
    if (bearing[i]) islandDepth[r] = std::max(islandDepth[r], levels[i]);
    const double im = solverBodies[i].invMass;
    if (im == 0.0) continue;
    islandLightest[r] = std::max(islandLightest[r], im);
    islandHeaviest[r] = std::min(islandHeaviest[r], im);
  }
  relaxPasses.resize(links.size());
  firstSubstepPasses.resize(links.size());
  for (size_t i = 0; i < links.size(); ++i) {
    const detail::ManifoldLink& l = links[i];
    const int body = levels[l.a] == 0 ? l.b : l.a;
    const int depth = islandDepth[root(body)];
    const int extra = depth > 12 ? (2 * (depth - 10) + 4) / 5 : 0;
    const int room = std::max(0, def.maxRelaxIterations - def.relaxIterations);
    relaxPasses[i] = def.relaxIterations + std::min(extra, room);
    // A contact that starts touching has no warm start: one pass leaves its normal, friction
    // and tipping out of balance (a cube set on a slope jumped 0.5 mm and slid 2 % too far).
    // A few more passes in its first substep converge it; later substeps start warm.
    firstSubstepPasses[i] = relaxPasses[i];
    if (l.coldTouch && relaxPasses[i] > 0)
      firstSubstepPasses[i] =
          std::max(relaxPasses[i], std::min(kColdPasses, def.maxRelaxIterations));
  }

  // Gauss-Seidel cannot hold a heavy body on a light one: each pass moves the heavy body by
  // about the light one's share, so a 1000:1 pair sinks through (and shock propagation, which
  // freezes the lower body, then hands the light body's push-out to the heavy one). Small
  // islands whose masses differ by more than kUnequalMass get their normal impulses solved
  // directly instead (solveNormalsDirectly); uniform piles never pay for it.
  solvedDirectly.assign(solverManifolds.size(), 0);
  directManifolds.clear();
  std::vector<int>& points = fill;  // reused scratch: normal rows per island root
  points.assign(n, 0);
  auto islandOfManifold = [&](const detail::ManifoldLink& l) {
    return root(levels[l.a] == 0 ? l.b : l.a);
  };
  for (const detail::ManifoldLink& l : links) points[islandOfManifold(l)] += l.count;
  std::vector<std::pair<int, int>>& tagged = directScratch;  // (island, manifold)
  tagged.clear();
  for (size_t i = 0; i < links.size(); ++i) {
    const int r = islandOfManifold(links[i]);
    if (points[r] > kDirectRows) continue;
    if (islandLightest[r] <= kUnequalMass * islandHeaviest[r]) continue;
    tagged.emplace_back(r, static_cast<int>(i));
    solvedDirectly[i] = 1;
    if (!solverManifolds[i].rowsReady) prepareRows(solverManifolds[i]);
    // Measured: anchor springs between a light and a heavy body feed a slowly growing
    // sideways rocking (1000:1, after 3 s); these patches rely on velocity friction alone.
    solverManifolds[i].anchored = false;
  }
  std::sort(tagged.begin(), tagged.end());
  inBothRegions([&](int region) {  // each region's own; the first thread's, those across too
    auto shock = [&](int i) { prepareShock(static_cast<size_t>(i)); };
    forManifolds(region, shock);
    if (region == 0) forManifolds(kAcross, shock);
  });
  // The load pass's supports: bodies that rest on one support alone (counted per upper body),
  // in chains down to a static body (ground up, a body's support comes before its own).
  std::vector<int>& supports = fill;  // reused scratch
  supports.assign(n, 0);
  auto upperOf = [](const detail::ManifoldLink& l) {
    return l.shockMoves == static_cast<uint8_t>(Moves::OnlyA)   ? l.a
           : l.shockMoves == static_cast<uint8_t>(Moves::OnlyB) ? l.b
                                                                : -1;
  };
  for (const detail::ManifoldLink& l : links)
    if (upperOf(l) >= 0) ++supports[upperOf(l)];
  grounded.assign(n, 0);
  for (int i : shockOrder) {
    const detail::ManifoldLink& l = links[i];
    const int upper = upperOf(l);
    if (upper < 0 || supports[upper] != 1) continue;
    const int lower = upper == l.a ? l.b : l.a;
    grounded[upper] = solverBodies[lower].invMass == 0.0 || grounded[lower];
  }
  soleSupports.clear(), soleSupportIslands.clear();
  for (auto it = shockOrder.rbegin(); it != shockOrder.rend(); ++it) {
    const int upper = upperOf(links[*it]);
    if (upper < 0 || supports[upper] != 1 || !grounded[upper]) continue;
    soleSupports.push_back(*it);
    soleSupportIslands.push_back(root(upper));
  }
  islandRefused.assign(n, 0);
  stats.directIslands = 0;
  for (size_t k = 0; k < tagged.size(); ++k) {
    directManifolds.push_back(tagged[k].second);
    if (k + 1 == tagged.size() || tagged[k + 1].first != tagged[k].first) {
      directManifolds.push_back(-1);
      ++stats.directIslands;
    }
  }
}

// The shock pass of a manifold moves only the body farther from the ground (none is frozen
// where both sit at one level, or where the island's normals are solved directly after).
void World::Impl::prepareShock(size_t i) {
  SolverManifold& m = solverManifolds[i];
  const int la = levels[m.a], lb = levels[m.b];
  Moves moves = la < lb ? Moves::OnlyB : lb < la ? Moves::OnlyA : Moves::Both;
  if (solvedDirectly[i]) moves = Moves::Both, m.block = false, m.direct = true;
  m.shockMoves = links[i].shockMoves = static_cast<uint8_t>(moves);
  m.shockReady = false;  // its coupling waits for the first shock pass (prepareShockRows)
}

}  // namespace grip
