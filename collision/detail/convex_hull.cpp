// Quickhull: start from a tetrahedron of extreme points, then repeatedly add the point farthest
// outside any face, replacing the faces it sees by a fan from their horizon. Everything is
// index based and iterated in index order, so the result is deterministic. Afterwards adjacent
// triangles that lie in one plane are merged into polygons (a box's 8 corners give 6 quads).
#include "collision/detail/convex_hull.hpp"

#include <algorithm>
#include <map>
#include <numeric>

#include "core/error.hpp"

namespace grip::detail {
namespace {

struct Tri {
  std::array<int, 3> v{};
  Vec3 n = Vec3::Zero();
  double d = 0.0;
  bool alive = true;
  std::vector<int> outside;  // points above this face, assigned to it
};

Tri makeTri(const std::vector<Vec3>& p, int a, int b, int c) {
  Tri t;
  t.v = {a, b, c};
  t.n = (p[b] - p[a]).cross(p[c] - p[a]);
  const double len = t.n.norm();
  if (len > 0.0) t.n /= len;
  t.d = t.n.dot(p[a]);
  return t;
}

double height(const Tri& t, const Vec3& x) {
  return t.n.dot(x) - t.d;
}

// The first tetrahedron: two extreme points, the farthest from their line, the farthest from
// their plane. Throws on degenerate input.
std::array<int, 4> initialSimplex(const std::vector<Vec3>& p, double eps, const char* field) {
  std::array<int, 6> ext{};
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (p[i][k] < p[ext[2 * k]][k]) ext[2 * k] = i;
      if (p[i][k] > p[ext[2 * k + 1]][k]) ext[2 * k + 1] = i;
    }
  }
  int a = 0, b = 0;
  double best = -1.0;
  for (int i = 0; i < 6; ++i)
    for (int j = i + 1; j < 6; ++j) {
      const double d = (p[ext[i]] - p[ext[j]]).squaredNorm();
      if (d > best) best = d, a = ext[i], b = ext[j];
    }
  if (std::sqrt(best) <= eps) throw Error(field, "points must not all coincide");
  const Vec3 ab = (p[b] - p[a]).normalized();
  int c = -1;
  best = eps;
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    const double d = (p[i] - p[a]).cross(ab).norm();
    if (d > best) best = d, c = i;
  }
  if (c < 0) throw Error(field, "points must not be collinear");
  const Vec3 n = (p[b] - p[a]).cross(p[c] - p[a]).normalized();
  int d = -1;
  best = eps;
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    const double h = std::abs(n.dot(p[i] - p[a]));
    if (h > best) best = h, d = i;
  }
  if (d < 0) throw Error(field, "points must not be coplanar (need a volume)");
  return {a, b, c, d};
}

class QuickHull {
 public:
  QuickHull(const std::vector<Vec3>& p, double eps) : p_(p), eps_(eps) {}

  void run(const std::array<int, 4>& s) {
    const Vec3 inner = 0.25 * (p_[s[0]] + p_[s[1]] + p_[s[2]] + p_[s[3]]);
    const int f[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    for (const auto& fi : f) {
      Tri t = makeTri(p_, s[fi[0]], s[fi[1]], s[fi[2]]);
      if (height(t, inner) > 0.0) t = makeTri(p_, s[fi[0]], s[fi[2]], s[fi[1]]);
      tris_.push_back(t);
    }
    std::vector<int> all;
    for (int i = 0; i < static_cast<int>(p_.size()); ++i)
      if (i != s[0] && i != s[1] && i != s[2] && i != s[3]) all.push_back(i);
    assign(all, 0);
    while (addFarthest()) {
    }
  }

  const std::vector<Tri>& tris() const { return tris_; }

 private:
  // Gives each point to the face (from `firstFace` on) it is farthest above.
  void assign(const std::vector<int>& pts, size_t firstFace) {
    for (int i : pts) {
      int best = -1;
      double bestH = eps_;
      for (size_t f = firstFace; f < tris_.size(); ++f) {
        if (!tris_[f].alive) continue;
        const double h = height(tris_[f], p_[i]);
        if (h > bestH) bestH = h, best = static_cast<int>(f);
      }
      if (best >= 0) tris_[best].outside.push_back(i);
    }
  }

  bool addFarthest() {
    int eye = -1;
    double bestH = eps_;
    for (const Tri& t : tris_) {
      if (!t.alive) continue;
      for (int i : t.outside) {
        const double h = height(t, p_[i]);
        if (h > bestH) bestH = h, eye = i;
      }
    }
    if (eye < 0) return false;
    // Faces seen from the eye, and their boundary (edges not shared by two visible faces).
    std::map<std::pair<int, int>, int> visibleEdges;
    std::vector<int> orphans;
    for (Tri& t : tris_) {
      if (!t.alive || height(t, p_[eye]) <= eps_) continue;
      t.alive = false;
      for (int k = 0; k < 3; ++k) visibleEdges[{t.v[k], t.v[(k + 1) % 3]}] = 1;
      for (int i : t.outside)
        if (i != eye) orphans.push_back(i);
      t.outside.clear();
    }
    const size_t first = tris_.size();
    for (const auto& [e, unused] : visibleEdges) {
      if (visibleEdges.count({e.second, e.first})) continue;
      tris_.push_back(makeTri(p_, e.first, e.second, eye));
    }
    std::sort(orphans.begin(), orphans.end());
    assign(orphans, first);
    return true;
  }

  const std::vector<Vec3>& p_;
  double eps_;
  std::vector<Tri> tris_;
};

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Boundary loop of a group of triangles: directed edges used once, chained head to tail.
std::vector<int> boundaryLoop(const std::vector<const Tri*>& group) {
  std::map<std::pair<int, int>, int> count;
  for (const Tri* t : group)
    for (int k = 0; k < 3; ++k) count[{t->v[k], t->v[(k + 1) % 3]}] += 1;
  std::map<int, int> next;
  for (const auto& [e, c] : count)
    if (!count.count({e.second, e.first})) next[e.first] = e.second;
  std::vector<int> loop;
  if (next.empty()) return loop;
  const int start = next.begin()->first;
  int v = start;
  do {
    loop.push_back(v);
    auto it = next.find(v);
    if (it == next.end() || loop.size() > next.size()) break;
    v = it->second;
  } while (v != start);
  return loop;
}

// Drops loop vertices that lie on the line through their neighbours.
std::vector<int> dropCollinear(const std::vector<Vec3>& p, std::vector<int> loop, double eps) {
  bool changed = true;
  while (changed && loop.size() > 3) {
    changed = false;
    for (size_t i = 0; i < loop.size(); ++i) {
      const Vec3& a = p[loop[(i + loop.size() - 1) % loop.size()]];
      const Vec3& b = p[loop[i]];
      const Vec3& c = p[loop[(i + 1) % loop.size()]];
      const double len = (c - a).norm();
      if (len > 0.0 && (b - a).cross(c - a).norm() / len <= eps) {
        loop.erase(loop.begin() + static_cast<long>(i));
        changed = true;
        break;
      }
    }
  }
  return loop;
}

}  // namespace

ConvexHullData buildConvexHull(const std::vector<Vec3>& points, const char* field) {
  double scale = 0.0;
  for (const Vec3& x : points) scale = std::max(scale, x.cwiseAbs().maxCoeff());
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& x : points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double eps = 1e-10 * std::max(scale, (hi - lo).maxCoeff()) + 1e-300;
  QuickHull qh(points, eps * 10.0);
  qh.run(initialSimplex(points, eps * 100.0, field));

  // Merge neighbouring triangles lying in one plane (union-find over shared edges).
  std::vector<const Tri*> tris;
  for (const Tri& t : qh.tris())
    if (t.alive) tris.push_back(&t);
  std::map<std::pair<int, int>, int> edgeTri;
  for (int i = 0; i < static_cast<int>(tris.size()); ++i)
    for (int k = 0; k < 3; ++k) edgeTri[{tris[i]->v[k], tris[i]->v[(k + 1) % 3]}] = i;
  std::vector<int> parent(tris.size());
  std::iota(parent.begin(), parent.end(), 0);
  const double planeEps = eps * 1000.0;
  for (int i = 0; i < static_cast<int>(tris.size()); ++i) {
    for (int k = 0; k < 3; ++k) {
      auto it = edgeTri.find({tris[i]->v[(k + 1) % 3], tris[i]->v[k]});
      if (it == edgeTri.end()) continue;
      const Tri& a = *tris[i];
      const Tri& b = *tris[it->second];
      // Coplanar when each triangle's far vertex lies on the other's plane.
      bool flat = a.n.dot(b.n) > 0.0;
      for (int m = 0; m < 3 && flat; ++m)
        flat = std::abs(height(a, points[b.v[m]])) <= planeEps &&
               std::abs(height(b, points[a.v[m]])) <= planeEps;
      if (flat) parent[findRoot(parent, i)] = findRoot(parent, it->second);
    }
  }
  std::map<int, std::vector<const Tri*>> groups;  // keyed by root: deterministic order
  for (int i = 0; i < static_cast<int>(tris.size()); ++i)
    groups[findRoot(parent, i)].push_back(tris[i]);

  ConvexHullData hull;
  std::vector<int> remap(points.size(), -1);
  for (const auto& [root, group] : groups) {
    std::vector<int> loop = dropCollinear(points, boundaryLoop(group), planeEps);
    if (loop.size() < 3) continue;
    ConvexHullData::Face face;
    // Newell's normal of the loop: robust for polygons with many vertices.
    Vec3 n = Vec3::Zero(), c = Vec3::Zero();
    for (size_t i = 0; i < loop.size(); ++i) {
      const Vec3& a = points[loop[i]];
      const Vec3& b = points[loop[(i + 1) % loop.size()]];
      n += a.cross(b);
      c += a;
    }
    face.normal = n.normalized();
    face.offset = face.normal.dot(c / static_cast<double>(loop.size()));
    for (int v : loop) {
      if (remap[v] < 0) {
        remap[v] = static_cast<int>(hull.vertices.size());
        hull.vertices.push_back(points[v]);
      }
      face.vertices.push_back(remap[v]);
    }
    hull.faces.push_back(std::move(face));
  }
  // Offsets from the farthest vertex so every vertex is on or below each face plane.
  for (auto& f : hull.faces)
    for (int v : f.vertices) f.offset = std::max(f.offset, f.normal.dot(hull.vertices[v]));
  std::map<std::pair<int, int>, int> edges;
  for (const auto& f : hull.faces)
    for (size_t i = 0; i < f.vertices.size(); ++i) {
      const int a = f.vertices[i], b = f.vertices[(i + 1) % f.vertices.size()];
      edges[{std::min(a, b), std::max(a, b)}] = 1;
    }
  for (const auto& [e, unused] : edges) hull.edges.push_back({e.first, e.second});
  for (const Vec3& v : hull.vertices) hull.centroid += v;
  hull.centroid /= static_cast<double>(hull.vertices.size());
  return hull;
}

}  // namespace grip::detail
