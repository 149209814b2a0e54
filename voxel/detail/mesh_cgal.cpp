// Everything that needs CGAL, in one translation unit (CGAL compiles slowly): reading OFF, OBJ,
// STL and PLY, validation and repair, and the exact unions of the procedural objects.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "core/mass.hpp"
#include "voxel/voxel.hpp"

namespace grip::voxel {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Polygon = std::vector<std::size_t>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr size_t kMaxFaces = 20'000'000;  // beyond this a "mesh" is not an object to hold
constexpr double kMinSize = 1e-4;         // m across: smaller is almost surely wrong units
constexpr double kMaxSize = 1e4;          // m across

std::string plural(size_t n, const char* what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// A count read as a double, as text, without converting it to an integer (a header's 4.7e32
// does not fit one: found by the fuzzer).
std::string countText(double x) {
  char text[64];
  std::snprintf(text, sizeof text, "%.0f", x);
  return std::string(text);
}

// OFF headers state the counts: check them against the file size before CGAL allocates for
// them, so a truncated or lying header gives a message instead of a huge allocation.
void checkOffHeader(const std::string& path, uintmax_t fileBytes) {
  std::ifstream f(path);
  std::vector<std::string> tokens;  // the keyword and the two counts, comments skipped
  std::string line;
  size_t headerLines = 0;
  while (tokens.size() < 3 && std::getline(f, line)) {
    ++headerLines;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream ls(line);
    std::string word;
    while (tokens.size() < 3 && ls >> word) tokens.push_back(word);
  }
  if (tokens.empty() || tokens[0].find("OFF") == std::string::npos)
    throw Error(path, "malformed OFF (no OFF keyword)");
  // CGAL's binary OFF reader adds the header's two 32-bit counts and converts their sum to an
  // int (undefined behaviour above 2^31: found by the fuzzer), and its n- and 4-dimensional
  // variants skip the checks below. No mesh tool writes them by default: refuse all three.
  if (tokens.size() > 1 && tokens[1].rfind("BINARY", 0) == 0)
    throw Error(path, "binary OFF is not supported (write the mesh as text OFF, OBJ, STL or PLY)");
  if (tokens[0].find('n') != std::string::npos || tokens[0].find('4') != std::string::npos)
    throw Error(path, "OFF variant '" + tokens[0] +
                          "' is not supported (only OFF and its C, N, ST forms in 3D)");
  double nv = -1, nf = -1;
  try {
    if (tokens.size() < 3) throw std::invalid_argument("missing");
    nv = std::stod(tokens[1]);
    nf = std::stod(tokens[2]);
  } catch (const std::exception&) {
    throw Error(path, "malformed OFF header (no vertex and face counts)");
  }
  if (nv < 0 || nf < 0) throw Error(path, "malformed OFF header (negative counts)");
  if (nf > static_cast<double>(kMaxFaces))
    throw Error(path, "absurd size: the header claims " + countText(nf) + " faces (limit " +
                          std::to_string(kMaxFaces) + ")");
  // Every vertex takes at least 6 bytes ("0 0 0\n"), every face 8 ("3 0 1 2\n").
  if (6.0 * nv + 8.0 * nf > static_cast<double>(fileBytes) + 16.0)
    throw Error(path, "truncated: the header claims " + countText(nv) + " vertices and " +
                          countText(nf) + " faces but the file has only " +
                          std::to_string(fileBytes) + " bytes");
  // CGAL reads face indices as doubles and converts them to size_t: a huge or non-finite
  // "index" is undefined behaviour there (found by fuzz/fuzz_mesh.cpp). No valid number in an
  // OFF body is that large (indices are below the vertex count, coordinates beyond 1e4 m are
  // refused anyway), so refuse them here.
  // A face line starts with its vertex count, for which CGAL allocates: it cannot exceed the
  // file size (found by the fuzzer: a count of 350 million, 2.8 GB).
  f.clear();
  f.seekg(0);
  size_t lineNo = 0, dataLines = 0;
  while (std::getline(f, line)) {
    ++lineNo;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    const bool faceLine = lineNo > headerLines &&
                          line.find_first_not_of(" \t\r") != std::string::npos &&
                          ++dataLines > static_cast<size_t>(nv);
    // Numbers as a stream reader finds them: "12-19" is 12 and -19 to CGAL (found by the
    // fuzzer), so every number strtod can start anywhere in the line is checked.
    bool first = true;
    for (const char* at = line.c_str(); *at != '\0';) {
      if (std::isspace(static_cast<unsigned char>(*at))) {
        ++at;
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(at, &end);
      if (end == at) {
        ++at;
        continue;
      }
      const std::string word(at, static_cast<size_t>(end - at));
      at = end;
      if (faceLine && first && v > static_cast<double>(fileBytes))
        throw Error(path, "truncated: the face on line " + std::to_string(lineNo) + " claims " +
                              word + " vertices");
      first = false;
      if (!std::isfinite(v))
        throw Error(path, "non-finite number on line " + std::to_string(lineNo));
      if (std::abs(v) > 1e15)
        throw Error(path, "absurd number '" + word + "' on line " + std::to_string(lineNo));
      if (faceLine && v < 0.0)  // an index converted to size_t (found by the fuzzer too)
        throw Error(path,
                    "negative number '" + word + "' in the face on line " + std::to_string(lineNo));
    }
  }
}

// PLY headers are checked before CGAL reads them: CGAL's reader adds a "property" to the last
// element without checking that there is one (undefined behaviour on a header whose property
// comes first; found by fuzz/fuzz_mesh.cpp), and it loops over element counts the file cannot
// hold.
void checkPlyHeader(const std::string& path, uintmax_t fileBytes) {
  std::ifstream f(path, std::ios::binary);
  std::string line;
  size_t lineNo = 0;
  bool elements = false;
  std::string element;  // the current one
  double total = 0.0;   // elements claimed
  while (std::getline(f, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string keyword;
    ls >> keyword;
    if (lineNo == 1) {
      if (keyword != "ply") throw Error(path, "malformed PLY (no \"ply\" on the first line)");
      continue;
    }
    const std::string at = " on line " + std::to_string(lineNo);
    if (keyword == "end_header") {
      // Every element takes at least one byte (ASCII: a digit; binary: one property).
      if (total > static_cast<double>(fileBytes))
        throw Error(path, "truncated: the header claims " + countText(total) +
                              " elements but the file has only " + std::to_string(fileBytes) +
                              " bytes");
      return;
    }
    if (keyword == "format") {
      std::string format;
      ls >> format;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        throw Error(path, "cannot parse as ply (unknown format \"" + format + "\"" + at + ")");
    }
    if (keyword == "property" && !elements)
      throw Error(path, "malformed PLY header: a property before any element" + at);
    // CGAL reads vertex coordinates as float or double only (another type: a null dereference).
    if (keyword == "property" && element == "vertex") {
      std::string type, name;
      ls >> type >> name;
      if ((name == "x" || name == "y" || name == "z") && type != "float" && type != "float32" &&
          type != "double" && type != "float64")
        throw Error(path, "malformed PLY header: vertex coordinate " + name + " has type '" + type +
                              "' (expected float or double)" + at);
    }
    if (keyword == "element") {
      std::string name, count;
      ls >> name >> count;
      double n = -1;
      try {
        size_t used = 0;
        n = std::stod(count, &used);
        if (used != count.size() || count.find_first_not_of("0123456789") != std::string::npos)
          n = -1;
      } catch (const std::exception&) {
      }
      if (name.empty() || n < 0)
        throw Error(path, "malformed PLY header: an element without a name and count" + at);
      if (n > static_cast<double>(kMaxFaces))
        throw Error(path, "absurd size: the header claims " + count + " " + name + " elements" +
                              at + " (limit " + std::to_string(kMaxFaces) + ")");
      total += n;
      elements = true;
      element = name;
    }
  }
  throw Error(path, "truncated: PLY header without \"end_header\"");
}

// After a failed parse of a text mesh: the line of the first number that is not finite ("nan",
// "inf", "1e400"), or 0. CGAL's readers just fail on those; this names the problem.
size_t firstNonFiniteLine(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  for (size_t n = 1; std::getline(f, line) && n < 100'000'000; ++n) {
    std::istringstream ls(line);
    std::string word;
    while (ls >> word) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end != word.c_str() && *end == '\0' && !std::isfinite(v)) return n;
    }
  }
  return 0;
}

// An ASCII STL must end with "endsolid"; a binary one must hold 84 + 50 n bytes.
void checkStl(const std::string& path, uintmax_t bytes) {
  std::ifstream f(path, std::ios::binary);
  std::string head(5, '\0');
  f.read(head.data(), 5);
  if (head == "solid") {
    std::ifstream t(path);
    std::string word, last;
    bool ended = false;
    while (t >> word) {
      if (word == "facet") ended = false;
      if (word == "endsolid") ended = true;
      last = word;
    }
    if (!ended && bytes >= 84) {
      // Might still be a binary STL whose header starts with "solid".
      f.seekg(80);
      uint32_t n = 0;
      f.read(reinterpret_cast<char*>(&n), 4);
      if (84 + 50ull * n == bytes) return;
    }
    if (!ended) throw Error(path, "truncated: ASCII STL without a final \"endsolid\"");
    return;
  }
  if (bytes < 84) throw Error(path, "truncated: too short for a binary STL header");
  f.seekg(80);
  uint32_t n = 0;
  f.read(reinterpret_cast<char*>(&n), 4);
  if (84 + 50ull * n != bytes)
    throw Error(path, "truncated or malformed binary STL: " + std::to_string(n) +
                          " triangles need " + std::to_string(84 + 50ull * n) +
                          " bytes, the file has " + std::to_string(bytes));
}

double signedVolume(const SurfaceMesh& m) {
  double v = 0.0;
  for (auto f : m.faces()) {
    auto h = m.halfedge(f);
    const Point& a = m.point(m.source(h));
    const Point& b = m.point(m.target(h));
    const Point& c = m.point(m.target(m.next(h)));
    v += CGAL::determinant(a - CGAL::ORIGIN, b - CGAL::ORIGIN, c - CGAL::ORIGIN) / 6.0;
  }
  return v;
}

SurfaceMesh toSurfaceMesh(const Mesh& in) {
  SurfaceMesh m;
  std::vector<SurfaceMesh::Vertex_index> vs;
  vs.reserve(in.vertices.size());
  for (const Vec3& p : in.vertices) vs.push_back(m.add_vertex(Point(p.x(), p.y(), p.z())));
  for (const auto& t : in.triangles)
    if (m.add_face(vs[static_cast<size_t>(t[0])], vs[static_cast<size_t>(t[1])],
                   vs[static_cast<size_t>(t[2])]) == SurfaceMesh::null_face())
      throw Error("mesh", "cannot build a half-edge mesh (non-manifold input)");
  return m;
}

Mesh fromSurfaceMesh(SurfaceMesh m) {
  m.collect_garbage();
  Mesh out;
  out.vertices.reserve(m.number_of_vertices());
  for (auto v : m.vertices()) {
    const Point& p = m.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  out.triangles.reserve(m.number_of_faces());
  for (auto f : m.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      if (k < 3) t[static_cast<size_t>(k)] = static_cast<int>(v.idx());
      ++k;
    }
    if (k != 3) throw Error("mesh", "internal: a face is not a triangle after triangulation");
    out.triangles.push_back(t);
  }
  return canonicalMesh(std::move(out));
}

// CGAL's default random generator is seeded from the clock (hole filling's Delaunay path uses
// it): reseeded before each use, the same input takes the same path every time (the fuzzer's
// fixed-seed run did not repeat itself without this).
void seedCgalRandom() {
  CGAL::get_default_random() = CGAL::Random(0);
}

// The repair pipeline on a polygon soup. `name` prefixes every message.
Mesh repairSoup(std::vector<Point> points, std::vector<Polygon> polygons, const std::string& name,
                const RepairOptions& opt, MeshReport& rep) {
  seedCgalRandom();
  rep.inputVertices = points.size();
  rep.inputFaces = polygons.size();
  if (polygons.empty())
    throw Error(name, points.empty() ? "empty mesh (no vertices, no faces)"
                                     : "empty mesh (no faces; a point cloud?)");
  if (polygons.size() > kMaxFaces)
    throw Error(name, "absurd size: " + plural(polygons.size(), "face") + " (limit " +
                          std::to_string(kMaxFaces) + ")");
  for (size_t i = 0; i < points.size(); ++i) {
    const Point& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw Error(name, "non-finite coordinate at vertex " + std::to_string(i));
  }
  for (size_t i = 0; i < polygons.size(); ++i) {
    if (polygons[i].size() < 3)
      throw Error(name, "face " + std::to_string(i) + " has fewer than 3 vertices");
    for (size_t v : polygons[i])
      if (v >= points.size())
        throw Error(name, "face " + std::to_string(i) + " uses vertex " + std::to_string(v) +
                              " but there are only " + plural(points.size(), "vertex"));
  }
  const CGAL::Bbox_3 box = CGAL::bbox_3(points.begin(), points.end());
  const double size =
      std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()});
  if (size > kMaxSize || size < kMinSize) {
    std::ostringstream s;
    s << "absurd size: the mesh is " << size << " m across (expected " << kMinSize << " to "
      << kMaxSize << " m; check the units)";
    throw Error(name, s.str());
  }

  // 1. Soup repair: merge duplicate vertices, drop degenerate and duplicate faces.
  const size_t nv = points.size(), nf = polygons.size();
  PMP::repair_polygon_soup(points, polygons);
  if (points.size() != nv)
    rep.repairs.push_back("merged or dropped " +
                          plural(nv - points.size(), "duplicate or unused vertex"));
  if (polygons.size() != nf)
    rep.repairs.push_back("removed " +
                          plural(nf - polygons.size(), "degenerate or duplicate face"));
  if (polygons.empty()) throw Error(name, "empty mesh (every face was degenerate)");

  // 2. An edge shared by more than two faces has no inside and outside: refuse.
  {
    std::map<std::pair<size_t, size_t>, int> edgeFaces;
    for (const Polygon& poly : polygons)
      for (size_t i = 0; i < poly.size(); ++i) {
        const size_t a = poly[i], b = poly[(i + 1) % poly.size()];
        ++edgeFaces[{std::min(a, b), std::max(a, b)}];
      }
    size_t bad = 0;
    for (const auto& [edge, count] : edgeFaces) bad += count > 2 ? 1 : 0;
    if (bad > 0)
      throw Error(name, "non-manifold: " + plural(bad, "edge") +
                            " shared by more than two faces, so the surface does not bound a "
                            "volume");
  }
  // 3. Consistent orientation. Where sheets meet at a single vertex CGAL splits the vertex;
  // the surface still bounds the same volume.
  const size_t beforeOrient = points.size();
  if (!PMP::orient_polygon_soup(points, polygons))
    rep.repairs.push_back("split " + plural(points.size() - beforeOrient, "non-manifold vertex"));
  // Polygons become triangle fans here, in the soup: CGAL 5.5's triangulate_faces writes to
  // freed memory on some non-planar quads (a fuzz finding, docs/fuzzing.md). A fan keeps the
  // orientation; a fan of a non-convex polygon overlaps itself and is caught in step 5.
  std::vector<Polygon> triangles;
  triangles.reserve(polygons.size());
  for (const Polygon& poly : polygons)
    for (size_t i = 1; i + 1 < poly.size(); ++i)
      triangles.push_back({poly[0], poly[i], poly[i + 1]});
  if (triangles.size() != polygons.size()) rep.repairs.push_back("triangulated polygons");
  if (!PMP::is_polygon_soup_a_polygon_mesh(triangles))
    throw Error(name, "non-manifold: the faces do not join into a surface");
  SurfaceMesh m;
  PMP::polygon_soup_to_polygon_mesh(points, triangles, m);

  // 4. Geometrically degenerate (zero-area) faces: collapse them away.
  size_t degenerate = 0;
  for (auto f : m.faces())
    if (PMP::is_degenerate_triangle_face(f, m)) ++degenerate;
  if (degenerate > 0) {
    if (PMP::remove_degenerate_faces(m)) {
      m.collect_garbage();
      rep.repairs.push_back("removed " + plural(degenerate, "zero-area face"));
    } else {
      rep.warnings.push_back(plural(degenerate, "zero-area face") + " could not be removed");
    }
    if (m.is_empty()) throw Error(name, "empty mesh (every face had zero area)");
  }

  // 5. Self-intersections make the volume ambiguous: report them.
  using FacePair = std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>;
  auto selfIntersections = [&m] {
    std::vector<FacePair> pairs;
    PMP::self_intersections(m, std::back_inserter(pairs));
    return pairs;
  };
  std::vector<FacePair> pairs = selfIntersections();
  if (!pairs.empty()) {
    const std::string what = "self-intersecting: " + plural(pairs.size(), "pair") +
                             " of faces intersect (first: faces " +
                             std::to_string(pairs[0].first.idx()) + " and " +
                             std::to_string(pairs[0].second.idx()) + ")";
    if (!opt.allowSelfIntersections)
      throw Error(name, what + "; fix the mesh or pass --allow-self-intersections");
    rep.warnings.push_back(what + "; mass properties count overlapping parts twice");
  }

  // 6. Holes: triangulate every boundary cycle (documented repair), or refuse. A filling that
  // makes the surface intersect itself or enclose nothing is refused, naming the holes.
  std::string holeProblem;
  std::vector<SurfaceMesh::Halfedge_index> holes;
  PMP::extract_boundary_cycles(m, std::back_inserter(holes));
  if (!holes.empty()) {
    size_t borderEdges = 0;
    for (auto h : holes) borderEdges += CGAL::halfedges_around_face(h, m).size();
    const std::string what =
        "open: " + plural(holes.size(), "hole") + " (" + plural(borderEdges, "boundary edge") + ")";
    if (!opt.fillHoles) throw Error(name, what + "; hole filling is disabled");
    size_t added = 0;
    for (auto h : holes) {
      std::vector<SurfaceMesh::Face_index> fs;
      PMP::triangulate_hole(m, h, std::back_inserter(fs));
      added += fs.size();
    }
    if (!CGAL::is_closed(m)) throw Error(name, what + " that could not all be closed");
    if (pairs.empty() && !selfIntersections().empty())
      throw Error(name, what +
                            " that cannot be closed into a solid (closing them makes the "
                            "surface intersect itself)");
    holeProblem = what;
    rep.repairs.push_back("filled " + plural(holes.size(), "hole") + " (" +
                          plural(borderEdges, "boundary edge") + ") with " +
                          plural(added, "triangle"));
  }

  // 7. Outward orientation (nested shells alternate, so cavities come out right).
  const double before = signedVolume(m);
  if (pairs.empty()) {
    PMP::orient_to_bound_a_volume(m);
  } else if (before < 0.0) {
    PMP::reverse_face_orientations(m);
  }
  const double after = signedVolume(m);
  if (after != before) rep.repairs.push_back("oriented the faces outward");
  if (!(after > 1e-12 * size * size * size)) {
    if (!holeProblem.empty())
      throw Error(name,
                  holeProblem + " that cannot be closed into a solid (it encloses no volume)");
    throw Error(name, "encloses no volume (flat or degenerate)");
  }
  return fromSurfaceMesh(std::move(m));
}

}  // namespace

Mesh loadMesh(const std::string& path, const RepairOptions& options, MeshReport* report) {
  const std::string ext = lowerExtension(path);
  if (ext != "off" && ext != "obj" && ext != "stl" && ext != "ply")
    throw Error(path, "unknown mesh format '" + (ext.empty() ? std::string("(none)") : "." + ext) +
                          "' (expected .off, .obj, .stl or .ply)");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(path, "no such file");
  const uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes == 0) throw Error(path, "empty file");
  if (ext == "off") checkOffHeader(path, bytes);
  if (ext == "stl") checkStl(path, bytes);
  if (ext == "ply") checkPlyHeader(path, bytes);
  std::vector<Point> points;
  std::vector<Polygon> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    throw Error(path, std::string("cannot parse (") + e.what() + ")");
  }
  if (!ok) {
    if (const size_t line = firstNonFiniteLine(path); line > 0)
      throw Error(path, "non-finite number on line " + std::to_string(line));
    throw Error(path, "cannot parse as " + ext + " (malformed or truncated)");
  }
  MeshReport local;
  return repairSoup(std::move(points), std::move(polygons), path, options,
                    report ? *report : local);
}

Mesh repairMesh(const Mesh& mesh, const RepairOptions& options, MeshReport* report) {
  std::vector<Point> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<Polygon> polygons;
  polygons.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    Polygon poly;
    for (int i : t) {
      if (i < 0) throw Error("mesh", "negative vertex index");
      poly.push_back(static_cast<size_t>(i));
    }
    polygons.push_back(std::move(poly));
  }
  MeshReport local;
  return repairSoup(std::move(points), std::move(polygons), "mesh", options,
                    report ? *report : local);
}

Mesh meshUnion(const std::vector<Mesh>& parts) {
  if (parts.empty()) throw Error("meshUnion", "no parts");
  seedCgalRandom();
  SurfaceMesh acc = toSurfaceMesh(parts[0]);
  for (size_t i = 1; i < parts.size(); ++i) {
    SurfaceMesh next = toSurfaceMesh(parts[i]);
    SurfaceMesh out;
    if (!PMP::corefine_and_compute_union(acc, next, out))
      throw Error("meshUnion", "CGAL could not compute the union with part " + std::to_string(i));
    acc = std::move(out);
  }
  return fromSurfaceMesh(std::move(acc));
}

}  // namespace grip::voxel
