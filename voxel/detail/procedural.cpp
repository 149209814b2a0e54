// Built-in concave test objects, made from simple closed primitives (surfaces of revolution,
// swept tubes, boxes, ellipsoids) joined by CGAL's exact union (meshUnion). Sizes in metres,
// Y up, resting on y = 0 where it makes sense.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>

#include "core/error.hpp"
#include "voxel/voxel.hpp"

namespace grip::voxel {

namespace {

double signedVolume(const Mesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += m.vertices[static_cast<size_t>(t[0])].dot(
             m.vertices[static_cast<size_t>(t[1])].cross(m.vertices[static_cast<size_t>(t[2])])) /
         6.0;
  return v;
}

// Generators below only guarantee a consistent winding; this makes it outward.
Mesh outward(Mesh m) {
  if (signedVolume(m) < 0.0)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

void quad(Mesh& m, int a, int b, int c, int d) {
  m.triangles.push_back({a, b, c});
  m.triangles.push_back({a, c, d});
}

// A closed surface of revolution about Y of a profile (r, y) whose first and last points lie on
// the axis (r = 0); the others have r > 0.
Mesh revolve(const std::vector<std::array<double, 2>>& profile, int segments) {
  Mesh m;
  const int n = static_cast<int>(profile.size());
  const int bottom = 0;
  m.vertices.emplace_back(0.0, profile.front()[1], 0.0);
  for (int i = 1; i < n - 1; ++i)
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * kPi * s / segments;
      m.vertices.emplace_back(profile[static_cast<size_t>(i)][0] * std::cos(phi),
                              profile[static_cast<size_t>(i)][1],
                              profile[static_cast<size_t>(i)][0] * std::sin(phi));
    }
  const int top = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0.0, profile.back()[1], 0.0);
  auto ring = [&](int i, int s) { return 1 + (i - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({bottom, ring(1, s + 1), ring(1, s)});
    for (int i = 1; i < n - 2; ++i)
      quad(m, ring(i, s), ring(i, s + 1), ring(i + 1, s + 1), ring(i + 1, s));
    m.triangles.push_back({top, ring(n - 2, s), ring(n - 2, s + 1)});
  }
  return outward(std::move(m));
}

Mesh transformed(Mesh m, const Transform& t) {
  for (Vec3& p : m.vertices) p = t.apply(p);
  return m;
}

Mesh ellipsoid(const Vec3& center, const Vec3& radii, const Quat& q = Quat::Identity()) {
  std::vector<std::array<double, 2>> profile;
  const int rings = 16;
  for (int i = 0; i <= rings; ++i) {
    const double th = kPi * i / rings;  // from the south pole up
    profile.push_back({i == 0 || i == rings ? 0.0 : std::sin(th), -std::cos(th)});
  }
  Mesh m = revolve(profile, 24);
  for (Vec3& p : m.vertices) p = p.cwiseProduct(radii);
  Transform t;
  t.p = center, t.q = q;
  return transformed(std::move(m), t);
}

Mesh cylinder(double radius, double y0, double y1, int segments) {
  return revolve({{0.0, y0}, {radius, y0}, {radius, y1}, {0.0, y1}}, segments);
}

Mesh box(const Vec3& lo, const Vec3& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                            (i & 4) ? hi.z() : lo.z());
  quad(m, 0, 2, 3, 1), quad(m, 4, 5, 7, 6), quad(m, 0, 1, 5, 4);
  quad(m, 2, 6, 7, 3), quad(m, 0, 4, 6, 2), quad(m, 1, 3, 7, 5);
  return outward(std::move(m));
}

// A hexahedron from two parallel quads (a "frustum"): corners i in bit order as in box().
Mesh hexahedron(const std::array<Vec3, 8>& c) {
  Mesh m;
  m.vertices.assign(c.begin(), c.end());
  quad(m, 0, 2, 3, 1), quad(m, 4, 5, 7, 6), quad(m, 0, 1, 5, 4);
  quad(m, 2, 6, 7, 3), quad(m, 0, 4, 6, 2), quad(m, 1, 3, 7, 5);
  return outward(std::move(m));
}

// A circular tube of `radius` swept along a planar path in the XY plane, capped at both ends.
Mesh tube(const std::vector<Vec3>& path, double radius, int sides) {
  Mesh m;
  const int n = static_cast<int>(path.size());
  for (int i = 0; i < n; ++i) {
    const Vec3 prev = path[static_cast<size_t>(std::max(i - 1, 0))];
    const Vec3 next = path[static_cast<size_t>(std::min(i + 1, n - 1))];
    const Vec3 t = (next - prev).normalized();
    const Vec3 nrm(-t.y(), t.x(), 0.0), bin = Vec3::UnitZ();
    for (int s = 0; s < sides; ++s) {
      const double phi = 2.0 * kPi * s / sides;
      m.vertices.push_back(path[static_cast<size_t>(i)] +
                           radius * (std::cos(phi) * nrm + std::sin(phi) * bin));
    }
  }
  auto at = [&](int i, int s) { return i * sides + (s % sides); };
  for (int i = 0; i + 1 < n; ++i)
    for (int s = 0; s < sides; ++s) quad(m, at(i, s), at(i, s + 1), at(i + 1, s + 1), at(i + 1, s));
  const int c0 = static_cast<int>(m.vertices.size());
  m.vertices.push_back(path.front());
  const int c1 = c0 + 1;
  m.vertices.push_back(path.back());
  for (int s = 0; s < sides; ++s) {
    m.triangles.push_back({c0, at(0, s + 1), at(0, s)});
    m.triangles.push_back({c1, at(n - 1, s), at(n - 1, s + 1)});
  }
  return outward(std::move(m));
}

Mesh torus(double major, double minor, int nu, int nv) {
  Mesh m;
  for (int u = 0; u < nu; ++u)
    for (int v = 0; v < nv; ++v) {
      const double a = 2.0 * kPi * u / nu, b = 2.0 * kPi * v / nv;
      const double r = major + minor * std::cos(b);
      m.vertices.emplace_back(r * std::cos(a), minor * std::sin(b), r * std::sin(a));
    }
  auto at = [&](int u, int v) { return (u % nu) * nv + (v % nv); };
  for (int u = 0; u < nu; ++u)
    for (int v = 0; v < nv; ++v) quad(m, at(u, v), at(u + 1, v), at(u + 1, v + 1), at(u, v + 1));
  return outward(std::move(m));
}

Mesh mug() {
  // Cup: outer radius 42 mm, inner 34 mm, 95 mm tall, 8 mm floor.
  const double ro = 0.042, ri = 0.034, h = 0.095, floor = 0.008;
  Mesh cup = revolve({{0.0, 0.0}, {ro, 0.0}, {ro, h}, {ri, h}, {ri, floor}, {0.0, floor}}, 48);
  // Handle: a 4.5 mm tube whose capped ends sit inside the wall (r = 38 mm), so the union
  // joins them to the cup without piercing the cavity.
  const double rm = 0.5 * (ro + ri), x0 = 0.054, yTop = 0.075, yBot = 0.025;
  const double arc = 0.5 * (yTop - yBot), yMid = 0.5 * (yTop + yBot);
  std::vector<Vec3> path;
  for (int i = 0; i <= 4; ++i) path.emplace_back(rm + (x0 - rm) * i / 4.0, yTop, 0.0);
  for (int i = 1; i < 24; ++i) {
    const double a = kPi * i / 24.0;  // from the top, clockwise around the outer side
    path.emplace_back(x0 + arc * std::sin(a), yMid + arc * std::cos(a), 0.0);
  }
  for (int i = 0; i <= 4; ++i) path.emplace_back(x0 + (rm - x0) * i / 4.0, yBot, 0.0);
  return meshUnion({cup, tube(path, 0.0045, 16)});
}

Mesh axe() {
  // A hatchet: 36 cm handle, a wedge head 4 cm thick at the back, 6 mm at the edge.
  Mesh handle = box({-0.014, 0.0, -0.0115}, {0.014, 0.36, 0.0115});
  const double xb = -0.028, xf = 0.1, yb0 = 0.27, yb1 = 0.33, yf0 = 0.235, yf1 = 0.355;
  const double zb = 0.02, zf = 0.003;
  std::array<Vec3, 8> c;
  for (int i = 0; i < 8; ++i) {
    const bool front = i & 1, up = i & 2, out = i & 4;
    c[static_cast<size_t>(i)] = Vec3(front ? xf : xb, front ? (up ? yf1 : yf0) : (up ? yb1 : yb0),
                                     (front ? zf : zb) * (out ? 1.0 : -1.0));
  }
  return meshUnion({handle, hexahedron(c)});
}

Mesh lBlock() {
  // 10 x 10 cm L, 3 cm thick arms, 5 cm deep.
  return meshUnion(
      {box({0.0, 0.0, 0.0}, {0.1, 0.03, 0.05}), box({0.0, 0.0, 0.0}, {0.03, 0.1, 0.05})});
}

Mesh figurine() {
  const Quat armR(Eigen::AngleAxisd(kPi / 6.0, Vec3::UnitZ()));
  const Quat armL(Eigen::AngleAxisd(-kPi / 6.0, Vec3::UnitZ()));
  return meshUnion({cylinder(0.04, 0.0, 0.01, 40),
                    ellipsoid({0.012, 0.04, 0.0}, {0.01, 0.032, 0.01}),
                    ellipsoid({-0.012, 0.04, 0.0}, {0.01, 0.032, 0.01}),
                    ellipsoid({0.0, 0.09, 0.0}, {0.022, 0.03, 0.016}),
                    ellipsoid({0.026, 0.095, 0.0}, {0.007, 0.025, 0.007}, armR),
                    ellipsoid({-0.026, 0.095, 0.0}, {0.007, 0.025, 0.007}, armL),
                    ellipsoid({0.0, 0.135, 0.0}, {0.017, 0.017, 0.017})});
}

}  // namespace

Mesh canonicalMesh(Mesh m) {
  std::vector<int> order(m.vertices.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  auto key = [&](int i) {
    const Vec3& p = m.vertices[static_cast<size_t>(i)];
    return std::array<double, 3>{p.x(), p.y(), p.z()};
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  std::vector<int> newIndex(order.size());
  Mesh out;
  out.vertices.reserve(order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    newIndex[static_cast<size_t>(order[i])] = static_cast<int>(i);
    out.vertices.push_back(m.vertices[static_cast<size_t>(order[i])]);
  }
  out.triangles.reserve(m.triangles.size());
  for (const auto& t : m.triangles) {
    std::array<int, 3> r{newIndex[static_cast<size_t>(t[0])], newIndex[static_cast<size_t>(t[1])],
                         newIndex[static_cast<size_t>(t[2])]};
    while (r[0] > r[1] || r[0] > r[2]) r = {r[1], r[2], r[0]};  // rotation keeps orientation
    out.triangles.push_back(r);
  }
  std::sort(out.triangles.begin(), out.triangles.end());
  return out;
}

std::vector<std::string> builtinNames() {
  return {"mug", "axe", "torus", "l-block", "figurine"};
}

Mesh builtinMesh(const std::string& name) {
  if (name == "mug") return mug();
  if (name == "axe") return axe();
  if (name == "torus") return torus(0.05, 0.015, 48, 24);
  if (name == "l-block") return lBlock();
  if (name == "figurine") return figurine();
  throw Error("builtin",
              "unknown built-in object '" + name + "' (mug, axe, torus, l-block, figurine)");
}

void writeMesh(const std::string& path, const Mesh& m) {
  const bool obj = path.size() >= 4 && path.compare(path.size() - 4, 4, ".obj") == 0;
  const bool off = path.size() >= 4 && path.compare(path.size() - 4, 4, ".off") == 0;
  if (!obj && !off) throw Error(path, "mesh export supports .off and .obj");
  std::ofstream f(path);
  if (!f) throw Error(path, "cannot open for writing");
  f << std::setprecision(9);
  if (off) f << "OFF\n" << m.vertices.size() << ' ' << m.triangles.size() << " 0\n";
  for (const Vec3& p : m.vertices)
    f << (obj ? "v " : "") << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : m.triangles) {
    if (obj)
      f << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    else
      f << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  }
  if (!f) throw Error(path, "write failed");
}

}  // namespace grip::voxel
