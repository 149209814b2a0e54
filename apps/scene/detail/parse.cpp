// Scene documents -> Scene, with every error naming its JSON path.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "scene/scene.hpp"

namespace grip::scene {

using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw Error(path.empty() ? "(scene)" : path, what);
}

std::string key(const std::string& path, const std::string& k) {
  return path.empty() ? k : path + "." + k;
}
std::string index(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string typeName(const json& j) {
  return j.type_name();
}

// The object at `path`; refuses fields not in `allowed`.
const json& object(const json& j, const std::string& path,
                   std::initializer_list<const char*> allowed) {
  if (!j.is_object()) fail(path, std::string("must be an object (got ") + typeName(j) + ")");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const bool ok =
        std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return it.key() == a; });
    if (!ok) fail(key(path, it.key()), "unknown field");
  }
  return j;
}

double number(const json& j, const std::string& path) {
  if (!j.is_number()) fail(path, std::string("must be a number (got ") + typeName(j) + ")");
  const double x = j.get<double>();
  if (!std::isfinite(x)) fail(path, "must be finite");
  return x;
}
double positive(const json& j, const std::string& path) {
  const double x = number(j, path);
  if (!(x > 0.0)) fail(path, "must be positive (got " + j.dump() + ")");
  return x;
}
double nonNegative(const json& j, const std::string& path) {
  const double x = number(j, path);
  if (x < 0.0) fail(path, "must not be negative (got " + j.dump() + ")");
  return x;
}
int integer(const json& j, const std::string& path, int lo, int hi) {
  if (!j.is_number_integer()) fail(path, std::string("must be an integer (got ") + j.dump() + ")");
  const auto x = j.get<int64_t>();
  if (x < lo || x > hi) {
    fail(path, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " +
                   std::to_string(x) + ")");
  }
  return static_cast<int>(x);
}
bool boolean(const json& j, const std::string& path) {
  if (!j.is_boolean()) fail(path, std::string("must be true or false (got ") + j.dump() + ")");
  return j.get<bool>();
}
std::string string(const json& j, const std::string& path) {
  if (!j.is_string()) fail(path, std::string("must be a string (got ") + typeName(j) + ")");
  return j.get<std::string>();
}
template <size_t N>
int choice(const json& j, const std::string& path, const std::array<const char*, N>& names) {
  const std::string s = string(j, path);
  for (size_t i = 0; i < N; ++i)
    if (s == names[i]) return static_cast<int>(i);
  std::string list;
  for (size_t i = 0; i < N; ++i) list += (i ? ", " : "") + std::string(names[i]);
  fail(path, "must be one of " + list + " (got \"" + s + "\")");
}
Vec3 vec3(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 3) fail(path, "must be an array of 3 numbers");
  return Vec3(number(j[0], index(path, 0)), number(j[1], index(path, 1)),
              number(j[2], index(path, 2)));
}
Vec3 positiveVec3(const json& j, const std::string& path) {
  const Vec3 v = vec3(j, path);
  for (int i = 0; i < 3; ++i) {
    if (!(v[i] > 0.0))
      fail(index(path, static_cast<size_t>(i)), "must be positive (got " + j[i].dump() + ")");
  }
  return v;
}
Vec3 direction(const json& j, const std::string& path) {
  const Vec3 v = vec3(j, path);
  if (v.norm() < 1e-9) fail(path, "must not be the zero vector");
  return v.normalized();
}
// [w, x, y, z] (normalized here) or {"axis": [x, y, z], "degrees": a}.
Quat orientation(const json& j, const std::string& path) {
  if (j.is_object()) {
    object(j, path, {"axis", "degrees"});
    if (!j.contains("axis")) fail(key(path, "axis"), "is required");
    if (!j.contains("degrees")) fail(key(path, "degrees"), "is required");
    const Vec3 axis = direction(j["axis"], key(path, "axis"));
    const double deg = number(j["degrees"], key(path, "degrees"));
    return Quat(Eigen::AngleAxisd(deg * kPi / 180.0, axis));
  }
  if (!j.is_array() || j.size() != 4) {
    fail(path, "must be a quaternion [w, x, y, z] or {\"axis\": [x, y, z], \"degrees\": a}");
  }
  Quat q(number(j[0], index(path, 0)), number(j[1], index(path, 1)), number(j[2], index(path, 2)),
         number(j[3], index(path, 3)));
  if (q.norm() < 1e-9) fail(path, "must be a non-zero quaternion");
  q.normalize();
  return q;
}

// Calls f(value, path) when the field exists.
template <class F>
void opt(const json& obj, const std::string& path, const char* k, F&& f) {
  if (obj.contains(k)) f(obj[k], key(path, k));
}

const json& required(const json& obj, const std::string& path, const char* k) {
  if (!obj.contains(k)) fail(key(path, k), "is required");
  return obj[k];
}

// ---- sections ---------------------------------------------------------------------------------

void parseWorld(const json& j, const std::string& path, Scene& s) {
  object(j, path,
         {"gravity", "hz", "dt", "substeps", "iterations", "positionIterations", "sleep",
          "contactHertz", "contactReuseDistance"});
  opt(j, path, "gravity",
      [&](const json& v, const std::string& p) { s.world.gravity = vec3(v, p); });
  if (j.contains("hz") && j.contains("dt")) fail(key(path, "dt"), "give either hz or dt, not both");
  opt(j, path, "hz", [&](const json& v, const std::string& p) {
    const double hz = positive(v, p);
    if (hz > 100000.0) fail(p, "must be at most 100000");
    s.dt = 1.0 / hz;
  });
  opt(j, path, "dt", [&](const json& v, const std::string& p) {
    s.dt = positive(v, p);
    if (s.dt > 1.0) fail(p, "must be at most 1 s");
  });
  opt(j, path, "substeps",
      [&](const json& v, const std::string& p) { s.world.substeps = integer(v, p, 1, 1000); });
  opt(j, path, "iterations", [&](const json& v, const std::string& p) {
    s.world.relaxIterations = integer(v, p, 0, 1000);
  });
  opt(j, path, "positionIterations", [&](const json& v, const std::string& p) {
    s.world.positionIterations = integer(v, p, 0, 1000);
  });
  opt(j, path, "sleep",
      [&](const json& v, const std::string& p) { s.world.enableSleep = boolean(v, p); });
  opt(j, path, "contactHertz",
      [&](const json& v, const std::string& p) { s.world.contactHertz = positive(v, p); });
  opt(j, path, "contactReuseDistance", [&](const json& v, const std::string& p) {
    s.world.contactReuseDistance = nonNegative(v, p);
  });
  // The scene's own step and substeps are kept; only a longer step would be cut finer.
  s.world.maxSubstep = std::max(s.world.maxSubstep, s.dt / s.world.substeps);
}

MaterialDef parseMaterial(const json& j, const std::string& path, MaterialDef m) {
  object(j, path, {"staticFriction", "dynamicFriction", "restitution", "density"});
  opt(j, path, "staticFriction",
      [&](const json& v, const std::string& p) { m.staticFriction = nonNegative(v, p); });
  opt(j, path, "dynamicFriction",
      [&](const json& v, const std::string& p) { m.dynamicFriction = nonNegative(v, p); });
  opt(j, path, "restitution", [&](const json& v, const std::string& p) {
    m.restitution = nonNegative(v, p);
    if (m.restitution > 1.0) fail(p, "must be at most 1");
  });
  opt(j, path, "density", [&](const json& v, const std::string& p) { m.density = positive(v, p); });
  if (m.dynamicFriction > m.staticFriction) {
    fail(key(path, "dynamicFriction"), "must not exceed staticFriction");
  }
  return m;
}

ShapePtr parsePrimitive(const json& j, const std::string& path, int type);

// A parsed shape; concave ones (asset, mesh) also bring the exact mass properties of their
// source mesh and the runtime asset file they came from.
struct ParsedShape {
  ShapePtr shape;
  bool isPlane = false;
  std::optional<MassProperties> exact;
  std::string asset;
};

// {"type": "asset", "path": ...} or {"type": "mesh", "path": ..., "lod": ...}: loads the runtime
// asset (preparing and caching the mesh first), relative paths from the scene file's folder.
ParsedShape parseConcave(const json& j, const std::string& path, bool mesh,
                         const std::string& baseDir, double density) {
  if (mesh) {
    object(j, path, {"type", "path", "lod"});
  } else {
    object(j, path, {"type", "path"});
  }
  const std::string pp = key(path, "path");
  const std::string file = resolvePath(baseDir, string(required(j, path, "path"), pp));
  std::string lod = "high";
  opt(j, path, "lod", [&](const json& v, const std::string& p) {
    lod = std::array{"low", "medium", "high",
                     "very-high"}[choice(v, p, std::array{"low", "medium", "high", "very-high"})];
  });
  ParsedShape out;
  try {
    if (mesh) {
      out.asset = preparedMeshAsset(file, lod, density);
    } else {
      std::error_code ec;
      if (std::filesystem::is_directory(file, ec))
        throw Error(file, "is a directory, not an asset file");
      if (!std::filesystem::is_regular_file(file, ec)) throw Error(file, "no such asset file");
      out.asset = file;
    }
    const LoadedAsset a = loadAsset(out.asset);
    out.shape = a.shape;
    out.exact = a.mass;
  } catch (const Error& e) {
    fail(pp, e.what());
  }
  return out;
}

ParsedShape parseShape(const json& j, const std::string& path, const std::string& baseDir,
                       double density) {
  if (!j.is_object()) fail(path, "must be an object with a \"type\"");
  const int type = choice(required(j, path, "type"), key(path, "type"),
                          std::array{"box", "sphere", "capsule", "plane", "hull", "asset", "mesh"});
  if (type >= 5) return parseConcave(j, path, type == 6, baseDir, density);
  ParsedShape out;
  out.isPlane = type == 3;
  out.shape = parsePrimitive(j, path, type);
  return out;
}

ShapePtr parsePrimitive(const json& j, const std::string& path, int type) {
  switch (type) {
    case 0: {
      object(j, path, {"type", "halfExtents", "rounding"});
      const Vec3 h = positiveVec3(required(j, path, "halfExtents"), key(path, "halfExtents"));
      double r = 0.0;
      opt(j, path, "rounding", [&](const json& v, const std::string& p) { r = nonNegative(v, p); });
      return Shape::box(h, r);
    }
    case 1:
      object(j, path, {"type", "radius"});
      return Shape::sphere(positive(required(j, path, "radius"), key(path, "radius")));
    case 2: {
      object(j, path, {"type", "radius", "halfHeight"});
      const double r = positive(required(j, path, "radius"), key(path, "radius"));
      const double hh = positive(required(j, path, "halfHeight"), key(path, "halfHeight"));
      return Shape::capsule(r, hh);
    }
    case 3: {
      object(j, path, {"type", "normal", "offset"});
      Vec3 n = Vec3::UnitY();
      double offset = 0.0;
      opt(j, path, "normal", [&](const json& v, const std::string& p) { n = direction(v, p); });
      opt(j, path, "offset", [&](const json& v, const std::string& p) { offset = number(v, p); });
      return Shape::plane(n, offset);
    }
    default: {
      object(j, path, {"type", "points", "rounding"});
      const json& pts = required(j, path, "points");
      const std::string pp = key(path, "points");
      if (!pts.is_array() || pts.size() < 4) fail(pp, "must be an array of at least 4 points");
      std::vector<Vec3> points;
      for (size_t i = 0; i < pts.size(); ++i) points.push_back(vec3(pts[i], index(pp, i)));
      double r = 0.0;
      opt(j, path, "rounding", [&](const json& v, const std::string& p) { r = nonNegative(v, p); });
      try {
        return Shape::convexHull(points, r);
      } catch (const Error& e) {
        fail(pp, e.what());
      }
    }
  }
}

BodyInteractionDef parseBodyInteraction(const json& j, const std::string& path) {
  object(j, path, {"gamma", "autoGamma", "staticFriction", "dynamicFriction"});
  BodyInteractionDef d;
  opt(j, path, "gamma", [&](const json& v, const std::string& p) { d.gamma = positive(v, p); });
  opt(j, path, "autoGamma",
      [&](const json& v, const std::string& p) { d.autoGamma = boolean(v, p); });
  opt(j, path, "staticFriction",
      [&](const json& v, const std::string& p) { d.staticFriction = positive(v, p); });
  opt(j, path, "dynamicFriction",
      [&](const json& v, const std::string& p) { d.dynamicFriction = positive(v, p); });
  return d;
}

// Kinds as a list of numbers from 0 to 63, one bit each.
uint64_t kinds(const json& j, const std::string& path) {
  if (!j.is_array()) fail(path, "must be an array of kinds (integers from 0 to 63)");
  uint64_t bits = 0;
  for (size_t i = 0; i < j.size(); ++i) bits |= uint64_t{1} << integer(j[i], index(path, i), 0, 63);
  return bits;
}

CollisionFilter parseFilter(const json& j, const std::string& path) {
  object(j, path, {"category", "mask", "group"});
  CollisionFilter f;
  opt(j, path, "category", [&](const json& v, const std::string& p) { f.category = kinds(v, p); });
  opt(j, path, "mask", [&](const json& v, const std::string& p) { f.mask = kinds(v, p); });
  opt(j, path, "group", [&](const json& v, const std::string& p) {
    f.group =
        integer(v, p, std::numeric_limits<int32_t>::min(), std::numeric_limits<int32_t>::max());
  });
  return f;
}

BodySpec parseBody(const json& j, const std::string& path, size_t i,
                   const std::map<std::string, MaterialDef>& materials,
                   const std::string& baseDir) {
  object(j, path,
         {"name", "type", "shape", "position", "orientation", "linearVelocity", "angularVelocity",
          "mass", "density", "material", "gravityScale", "linearDamping", "angularDamping",
          "allowSleep", "filter", "interaction"});
  BodySpec b;
  BodyDef& d = b.def;
  d.name = "body" + std::to_string(i);
  opt(j, path, "name", [&](const json& v, const std::string& p) {
    d.name = string(v, p);
    if (d.name.empty()) fail(p, "must not be empty");
  });
  opt(j, path, "type", [&](const json& v, const std::string& p) {
    d.type =
        std::array{BodyType::Dynamic, BodyType::Static,
                   BodyType::Kinematic}[choice(v, p, std::array{"dynamic", "static", "kinematic"})];
  });
  // Density first: a mesh is prepared at the body's density.
  if (j.contains("mass") && j.contains("density"))
    fail(key(path, "density"), "give either mass or density, not both");
  std::optional<double> density;
  opt(j, path, "density", [&](const json& v, const std::string& p) { density = positive(v, p); });
  const ParsedShape shape =
      parseShape(required(j, path, "shape"), key(path, "shape"), baseDir, density.value_or(1000.0));
  d.shape = shape.shape;
  b.asset = shape.asset;
  if (shape.isPlane && d.type != BodyType::Static)
    fail(key(path, "type"), "a plane must be static");
  opt(j, path, "material", [&](const json& v, const std::string& p) {
    if (v.is_string()) {
      const auto it = materials.find(v.get<std::string>());
      if (it == materials.end()) fail(p, "unknown material \"" + v.get<std::string>() + "\"");
      d.material = it->second;
    } else {
      d.material = parseMaterial(v, p, MaterialDef{});
    }
  });
  opt(j, path, "position", [&](const json& v, const std::string& p) { d.position = vec3(v, p); });
  opt(j, path, "orientation",
      [&](const json& v, const std::string& p) { d.orientation = orientation(v, p); });
  opt(j, path, "linearVelocity",
      [&](const json& v, const std::string& p) { d.linearVelocity = vec3(v, p); });
  opt(j, path, "angularVelocity",
      [&](const json& v, const std::string& p) { d.angularVelocity = vec3(v, p); });
  opt(j, path, "mass", [&](const json& v, const std::string& p) { d.mass = positive(v, p); });
  if (density) d.material.density = *density;
  // A concave body weighs what its source mesh weighs (exact), not what its voxel boxes do.
  if (shape.exact && d.mass == 0.0) {
    d.mass = density ? shape.exact->volume * *density : shape.exact->mass;
  }
  opt(j, path, "gravityScale",
      [&](const json& v, const std::string& p) { d.gravityScale = number(v, p); });
  opt(j, path, "linearDamping",
      [&](const json& v, const std::string& p) { d.linearDamping = nonNegative(v, p); });
  opt(j, path, "angularDamping",
      [&](const json& v, const std::string& p) { d.angularDamping = nonNegative(v, p); });
  opt(j, path, "allowSleep",
      [&](const json& v, const std::string& p) { d.allowSleep = boolean(v, p); });
  opt(j, path, "filter",
      [&](const json& v, const std::string& p) { d.filter = parseFilter(v, p); });
  opt(j, path, "interaction",
      [&](const json& v, const std::string& p) { b.interaction = parseBodyInteraction(v, p); });
  return b;
}

void parseInteraction(const json& j, const std::string& path, InteractionDef& d) {
  object(j, path,
         {"method", "gamma", "slipLaw", "contactPoint", "contactOffset", "releaseMargin",
          "patchSamples", "surfaceUpdates", "skinStaticFriction", "skinDynamicFriction",
          "kinematicGripForce", "trackingGrace", "teleportDistance", "touchable"});
  opt(j, path, "method", [&](const json& v, const std::string& p) {
    d.method = choice(v, p, std::array{"coulomb", "kinematic"}) == 0 ? InteractionMethod::Friction
                                                                     : InteractionMethod::Kinematic;
  });
  opt(j, path, "gamma", [&](const json& v, const std::string& p) { d.gamma = positive(v, p); });
  opt(j, path, "slipLaw", [&](const json& v, const std::string& p) {
    d.slipLaw = choice(v, p, std::array{"kinetic", "thesis"}) == 0 ? SlipLaw::KineticCoulomb
                                                                   : SlipLaw::ThesisLiteral;
  });
  opt(j, path, "contactPoint", [&](const json& v, const std::string& p) {
    d.contactPoint = std::array{
        ContactPointMethod::Auto, ContactPointMethod::RayCast,
        ContactPointMethod::ClosestPoint}[choice(v, p, std::array{"auto", "raycast", "closest"})];
  });
  opt(j, path, "contactOffset",
      [&](const json& v, const std::string& p) { d.contactOffset = positive(v, p); });
  opt(j, path, "releaseMargin",
      [&](const json& v, const std::string& p) { d.releaseMargin = nonNegative(v, p); });
  opt(j, path, "patchSamples", [&](const json& v, const std::string& p) {
    d.patchSamples = integer(v, p, 1, 9);
    if (d.patchSamples != 1 && d.patchSamples != 5 && d.patchSamples != 9)
      fail(p, "must be 1, 5 or 9");
  });
  opt(j, path, "surfaceUpdates",
      [&](const json& v, const std::string& p) { d.surfaceUpdates = boolean(v, p); });
  opt(j, path, "skinStaticFriction",
      [&](const json& v, const std::string& p) { d.skin.staticFriction = positive(v, p); });
  opt(j, path, "skinDynamicFriction",
      [&](const json& v, const std::string& p) { d.skin.dynamicFriction = positive(v, p); });
  if (d.skin.dynamicFriction > d.skin.staticFriction) {
    fail(key(path, "skinDynamicFriction"), "must not exceed skinStaticFriction");
  }
  opt(j, path, "kinematicGripForce",
      [&](const json& v, const std::string& p) { d.kinematicGripForce = positive(v, p); });
  opt(j, path, "trackingGrace",
      [&](const json& v, const std::string& p) { d.trackingGrace = nonNegative(v, p); });
  opt(j, path, "teleportDistance",
      [&](const json& v, const std::string& p) { d.teleportDistance = positive(v, p); });
  opt(j, path, "touchable",
      [&](const json& v, const std::string& p) { d.touchable.mask = kinds(v, p); });
}

int boneByName(const json& j, const std::string& path) {
  const std::string s = string(j, path);
  for (int b = 0; b < kBonesPerHand; ++b)
    if (s == boneName(b)) return b;
  fail(path,
       "unknown bone \"" + s + "\" (palm, thumb_metacarpal, ..., index_distal, ..., pinky_distal)");
}

KeySpec parseKey(const json& j, const std::string& path) {
  object(j, path, {"time", "palm", "pose", "park", "pinch", "press", "tracked"});
  KeySpec k;
  k.time = nonNegative(required(j, path, "time"), key(path, "time"));
  opt(j, path, "palm", [&](const json& v, const std::string& p) {
    object(v, p, {"position", "orientation"});
    Transform t;
    t.p = vec3(required(v, p, "position"), key(p, "position"));
    opt(v, p, "orientation",
        [&](const json& o, const std::string& op) { t.q = orientation(o, op); });
    k.palm = t;
  });
  opt(j, path, "pose", [&](const json& v, const std::string& p) {
    if (!k.palm) fail(p, "needs a \"palm\" to pose the hand at");
    k.pose =
        static_cast<GraspPose>(choice(v, p, std::array{"open", "pinch", "power", "flat", "point"}));
  });
  opt(j, path, "park", [&](const json& v, const std::string& p) {
    if (k.palm) fail(p, "give either palm or park, not both");
    k.park = vec3(v, p);
  });
  opt(j, path, "pinch", [&](const json& v, const std::string& p) {
    if (k.palm) fail(p, "cannot be combined with palm");
    object(v, p, {"center", "halfWidth", "depth"});
    PinchSpec s;
    s.center = vec3(required(v, p, "center"), key(p, "center"));
    s.halfWidth = positive(required(v, p, "halfWidth"), key(p, "halfWidth"));
    s.depth = number(required(v, p, "depth"), key(p, "depth"));
    k.pinch = s;
  });
  opt(j, path, "press", [&](const json& v, const std::string& p) {
    if (!v.is_array()) fail(p, "must be an array");
    for (size_t i = 0; i < v.size(); ++i) {
      const std::string bp = index(p, i);
      object(v[i], bp, {"bone", "point", "normal", "axis", "depth"});
      BonePress b;
      b.bone = boneByName(required(v[i], bp, "bone"), key(bp, "bone"));
      b.point = vec3(required(v[i], bp, "point"), key(bp, "point"));
      b.normal = direction(required(v[i], bp, "normal"), key(bp, "normal"));
      b.axis = direction(required(v[i], bp, "axis"), key(bp, "axis"));
      b.depth = number(required(v[i], bp, "depth"), key(bp, "depth"));
      k.press.push_back(b);
    }
  });
  opt(j, path, "tracked", [&](const json& v, const std::string& p) { k.tracked = boolean(v, p); });
  return k;
}

// ---- recorded tracking files (docs/scenes.md, "Tracking files") ---------------------------------

// [x, y, z, qw, qx, qy, qz]
Transform jointPose(const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 7) fail(path, "must be [x, y, z, qw, qx, qy, qz]");
  Transform t;
  t.p = Vec3(number(j[0], index(path, 0)), number(j[1], index(path, 1)),
             number(j[2], index(path, 2)));
  Quat q(number(j[3], index(path, 3)), number(j[4], index(path, 4)), number(j[5], index(path, 5)),
         number(j[6], index(path, 6)));
  if (q.norm() < 1e-9) fail(path, "has a zero quaternion");
  t.q = q.normalized();
  return t;
}

HandPose openXRFrame(const json& f, const std::string& path) {
  object(f, path, {"time", "active", "joints"});
  OpenXRHandFrame x;
  x.isActive = true;
  opt(f, path, "active", [&](const json& v, const std::string& p) { x.isActive = boolean(v, p); });
  if (!x.isActive) return HandPose{};
  const json& joints = required(f, path, "joints");
  const std::string jp = key(path, "joints");
  if (!joints.is_array() || joints.size() != kXrJointCount) {
    fail(jp,
         "must be an array of the 26 XR_EXT_hand_tracking joints (palm, wrist, thumb "
         "metacarpal, ...)");
  }
  for (size_t k = 0; k < joints.size(); ++k) {
    x.joints[k] = jointPose(joints[k], index(jp, k));
    x.valid[k] = true;
  }
  return fromOpenXR(x);
}

HandPose leapFrame(const json& f, const std::string& path, const LeapConversion& c) {
  object(f, path, {"time", "tracked", "palm", "digits"});
  LeapHandFrame l;
  l.isTracked = true;
  opt(f, path, "tracked",
      [&](const json& v, const std::string& p) { l.isTracked = boolean(v, p); });
  if (!l.isTracked) return HandPose{};
  const json& palm = required(f, path, "palm");
  const std::string pp = key(path, "palm");
  object(palm, pp, {"position", "normal", "direction"});
  l.palmPosition = vec3(required(palm, pp, "position"), key(pp, "position"));
  l.palmNormal = direction(required(palm, pp, "normal"), key(pp, "normal"));
  l.palmDirection = direction(required(palm, pp, "direction"), key(pp, "direction"));
  const json& digits = required(f, path, "digits");
  const std::string dp = key(path, "digits");
  if (!digits.is_array() || digits.size() != 5) fail(dp, "must be 5 digits, thumb to pinky");
  for (size_t d = 0; d < 5; ++d) {
    const std::string di = index(dp, d);
    if (!digits[d].is_array() || digits[d].size() != 4) {
      fail(di, "must be 4 bones: metacarpal, proximal, intermediate, distal");
    }
    for (size_t b = 0; b < 4; ++b) {
      const std::string bi = index(di, b);
      if (!digits[d][b].is_array() || digits[d][b].size() != 2) {
        fail(bi, "must be [prevJoint, nextJoint]");
      }
      l.digits[d][b] = {vec3(digits[d][b][0], index(bi, 0)), vec3(digits[d][b][1], index(bi, 1))};
    }
  }
  const HandPose pose = fromLeap(l, c);
  if (!pose.tracked) fail(pp, "palm normal and direction must not be parallel");
  return pose;
}

}  // namespace

std::vector<std::pair<double, HandPose>> parseTracking(const json& doc) {
  object(doc, "", {"format", "version", "source", "leap", "frames"});
  if (required(doc, "", "format") != "grip-tracking") {
    fail("format", "must be \"grip-tracking\" (got " + doc["format"].dump() + ")");
  }
  const json& version = required(doc, "", "version");
  if (version != 1)
    fail("version", "unsupported version " + version.dump() + " (this grip reads 1)");
  const bool leap =
      choice(required(doc, "", "source"), "source", std::array{"openxr", "leap"}) == 1;
  LeapConversion conv = LeapConversion::desktop();
  opt(doc, "", "leap", [&](const json& v, const std::string& p) {
    if (!leap) fail(p, "applies to \"source\": \"leap\" only");
    object(v, p, {"mount", "leftHanded"});
    opt(v, p, "mount", [&](const json& m, const std::string& mp) {
      conv = std::array{
          LeapConversion::desktop(), LeapConversion::riftDK2(),
          LeapConversion::holoLens()}[choice(m, mp, std::array{"desktop", "rift-dk2", "hololens"})];
    });
    opt(v, p, "leftHanded",
        [&](const json& b, const std::string& bp) { conv.sourceLeftHanded = boolean(b, bp); });
  });
  const json& frames = required(doc, "", "frames");
  if (!frames.is_array() || frames.empty()) fail("frames", "must be a non-empty array");
  std::vector<std::pair<double, HandPose>> out;
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::string fp = index("frames", i);
    if (!frames[i].is_object()) fail(fp, "must be an object");
    const double t = nonNegative(required(frames[i], fp, "time"), key(fp, "time"));
    if (!out.empty() && !(t > out.back().first)) {
      fail(key(fp, "time"), "must be later than the frame before");
    }
    out.emplace_back(t, leap ? leapFrame(frames[i], fp, conv) : openXRFrame(frames[i], fp));
  }
  return out;
}

namespace {

HandSpec parseHand(const json& j, const std::string& path, size_t i, const std::string& baseDir) {
  object(j, path,
         {"name", "side", "scale", "keyframes", "tracking", "positionNoise", "rotationNoise",
          "trackingLoss"});
  HandSpec h;
  h.def.name = "hand" + std::to_string(i);
  opt(j, path, "name", [&](const json& v, const std::string& p) {
    h.def.name = string(v, p);
    if (h.def.name.empty()) fail(p, "must not be empty");
  });
  opt(j, path, "side", [&](const json& v, const std::string& p) {
    h.def.side =
        choice(v, p, std::array{"right", "left"}) == 0 ? Handedness::Right : Handedness::Left;
  });
  opt(j, path, "scale", [&](const json& v, const std::string& p) { h.def.scale = positive(v, p); });
  opt(j, path, "positionNoise",
      [&](const json& v, const std::string& p) { h.positionNoise = nonNegative(v, p); });
  opt(j, path, "rotationNoise",
      [&](const json& v, const std::string& p) { h.rotationNoise = nonNegative(v, p); });
  opt(j, path, "trackingLoss", [&](const json& v, const std::string& p) {
    if (!v.is_array()) fail(p, "must be an array of [start, end] pairs");
    for (size_t k = 0; k < v.size(); ++k) {
      const std::string ip = index(p, k);
      if (!v[k].is_array() || v[k].size() != 2) fail(ip, "must be [start, end]");
      const double a = nonNegative(v[k][0], index(ip, 0)), b = nonNegative(v[k][1], index(ip, 1));
      if (b < a) fail(index(ip, 1), "must not be before the start");
      h.trackingLoss.emplace_back(a, b);
    }
  });
  if (j.contains("tracking")) {
    const std::string tp = key(path, "tracking");
    if (j.contains("keyframes")) fail(tp, "give either keyframes or tracking, not both");
    if (h.positionNoise > 0.0 || h.rotationNoise > 0.0)
      fail(key(path, "positionNoise"), "applies to keyframed hands only");
    const std::string file = resolvePath(baseDir, string(j["tracking"], tp));
    try {
      h.tracked = parseTracking(readJsonFile(file, "tracking file"));
    } catch (const Error& e) {
      const std::string what = e.what();
      // Errors from inside the file: "<file>: <json path>: <what>".
      fail(tp, what.rfind(file, 0) == 0 ? what : file + ": " + what);
    }
    return h;
  }
  const json& keys = required(j, path, "keyframes");
  const std::string kp = key(path, "keyframes");
  if (!keys.is_array() || keys.empty()) fail(kp, "must be a non-empty array");
  for (size_t k = 0; k < keys.size(); ++k) {
    h.keys.push_back(parseKey(keys[k], index(kp, k)));
    if (k > 0 && !(h.keys[k].time > h.keys[k - 1].time)) {
      fail(key(index(kp, k), "time"), "must be later than the keyframe before");
    }
  }
  const bool anyPalm = std::any_of(h.keys.begin(), h.keys.end(),
                                   [](const KeySpec& k) { return k.palm.has_value(); });
  if ((h.positionNoise > 0.0 || h.rotationNoise > 0.0) && anyPalm &&
      !std::all_of(h.keys.begin(), h.keys.end(),
                   [](const KeySpec& k) { return k.palm && k.press.empty(); })) {
    fail(key(path, "positionNoise"), "tracking noise needs palm keyframes only");
  }
  return h;
}

int bodyByName(const json& j, const std::string& path, const Scene& s) {
  const std::string name = string(j, path);
  for (size_t i = 0; i < s.bodies.size(); ++i)
    if (s.bodies[i].def.name == name) return static_cast<int>(i);
  fail(path, "unknown body \"" + name + "\"");
}

JointSpec parseJoint(const json& j, const std::string& path, const Scene& s) {
  object(j, path,
         {"type", "a", "b", "anchor", "anchorB", "axis", "limit", "cone", "motor", "spring",
          "collideConnected", "breakForce", "breakTorque"});
  JointSpec js;
  JointDef& d = js.def;
  d.type =
      static_cast<JointType>(choice(required(j, path, "type"), key(path, "type"), kJointTypeNames));
  js.a = bodyByName(required(j, path, "a"), key(path, "a"), s);
  js.b = bodyByName(required(j, path, "b"), key(path, "b"), s);
  if (js.a == js.b) fail(key(path, "b"), "must be another body than a");
  auto dynamic = [&](int i) {
    return s.bodies[static_cast<size_t>(i)].def.type == BodyType::Dynamic;
  };
  if (!dynamic(js.a) && !dynamic(js.b)) fail(path, "needs a dynamic body (a or b)");
  d.anchor = vec3(required(j, path, "anchor"), key(path, "anchor"));
  if (d.type == JointType::Distance) {
    d.anchorB = vec3(required(j, path, "anchorB"), key(path, "anchorB"));
    if (!((d.anchorB - d.anchor).norm() > 1e-6))
      fail(key(path, "anchorB"), "must be apart from anchor (a distance joint's length)");
  } else if (j.contains("anchorB")) {
    fail(key(path, "anchorB"), "only distance joints have a second anchor");
  }
  opt(j, path, "axis", [&](const json& v, const std::string& p) { d.axis = direction(v, p); });
  opt(j, path, "limit", [&](const json& v, const std::string& p) {
    if (!hasAxisPosition(d.type)) fail(p, "only hinges, sliders and distance joints have limits");
    if (!v.is_array() || v.size() != 2) fail(p, "must be [lower, upper]");
    d.enableLimit = true;
    d.lower = number(v[0], index(p, 0)), d.upper = number(v[1], index(p, 1));
    if (d.lower > d.upper) fail(index(p, 0), "must not exceed upper");
    if (d.type == JointType::Hinge && (d.lower < -kPi || d.upper > kPi))
      fail(p, "a hinge's limits must be within [-pi, pi] rad");
  });
  opt(j, path, "cone", [&](const json& v, const std::string& p) {
    if (d.type != JointType::Ball) fail(p, "only ball joints have a cone");
    d.enableCone = true;
    d.coneAngle = number(v, p);
    if (!(d.coneAngle > 0.0 && d.coneAngle < kPi)) fail(p, "must be within (0, pi) rad");
  });
  opt(j, path, "motor", [&](const json& v, const std::string& p) {
    if (!hasAxisPosition(d.type)) fail(p, "only hinges, sliders and distance joints have motors");
    object(v, p, {"speed", "maxForce"});
    d.enableMotor = true;
    opt(v, p, "speed", [&](const json& x, const std::string& xp) { d.motorSpeed = number(x, xp); });
    d.maxMotorForce = nonNegative(required(v, p, "maxForce"), key(p, "maxForce"));
  });
  opt(j, path, "spring", [&](const json& v, const std::string& p) {
    if (!hasAxisPosition(d.type)) fail(p, "only hinges, sliders and distance joints have springs");
    object(v, p, {"hertz", "dampingRatio", "target"});
    d.enableSpring = true;
    d.springHertz = positive(required(v, p, "hertz"), key(p, "hertz"));
    opt(v, p, "dampingRatio",
        [&](const json& x, const std::string& xp) { d.springDampingRatio = nonNegative(x, xp); });
    opt(v, p, "target",
        [&](const json& x, const std::string& xp) { d.springTarget = number(x, xp); });
  });
  opt(j, path, "collideConnected",
      [&](const json& v, const std::string& p) { d.collideConnected = boolean(v, p); });
  opt(j, path, "breakForce",
      [&](const json& v, const std::string& p) { d.breakForce = positive(v, p); });
  opt(j, path, "breakTorque",
      [&](const json& v, const std::string& p) { d.breakTorque = positive(v, p); });
  return js;
}

CheckSpec parseCheck(const json& j, const std::string& path, const Scene& s) {
  object(j, path,
         {"kind", "label", "body", "bodies", "except", "hand", "axis", "min", "max", "since"});
  CheckSpec c;
  c.kind = static_cast<CheckKind>(choice(
      required(j, path, "kind"), key(path, "kind"),
      std::array{"position", "displacement", "speed", "lowestHeight", "handContacts", "angle"}));
  opt(j, path, "label", [&](const json& v, const std::string& p) { c.label = string(v, p); });
  if (c.kind == CheckKind::HandContacts) {
    const std::string hp = key(path, "hand");
    const std::string name = string(required(j, path, "hand"), hp);
    for (size_t i = 0; i < s.hands.size(); ++i)
      if (s.hands[i].def.name == name) c.hand = static_cast<int>(i);
    if (c.hand < 0) fail(hp, "unknown hand \"" + name + "\"");
  } else if (j.contains("bodies")) {
    const json& v = j["bodies"];
    const std::string bp = key(path, "bodies");
    if (v == "*") {
      std::set<int> except;
      opt(j, path, "except", [&](const json& e, const std::string& ep) {
        if (!e.is_array()) fail(ep, "must be an array of body names");
        for (size_t i = 0; i < e.size(); ++i) except.insert(bodyByName(e[i], index(ep, i), s));
      });
      for (size_t i = 0; i < s.bodies.size(); ++i) {
        if (s.bodies[i].def.type == BodyType::Dynamic && !except.count(static_cast<int>(i))) {
          c.bodies.push_back(static_cast<int>(i));
        }
      }
    } else {
      if (!v.is_array() || v.empty()) fail(bp, "must be \"*\" or a non-empty array of body names");
      for (size_t i = 0; i < v.size(); ++i) c.bodies.push_back(bodyByName(v[i], index(bp, i), s));
    }
  } else {
    c.bodies.push_back(bodyByName(required(j, path, "body"), key(path, "body"), s));
  }
  opt(j, path, "axis", [&](const json& v, const std::string& p) { c.axis = direction(v, p); });
  opt(j, path, "since", [&](const json& v, const std::string& p) {
    if (c.kind != CheckKind::Displacement && c.kind != CheckKind::Angle) {
      fail(p, "applies to displacement and angle checks only");
    }
    c.since = nonNegative(v, p);
    if (c.since >= s.duration) fail(p, "must be before the end of the run (duration)");
  });
  if (c.kind == CheckKind::Angle && !c.axis)
    fail(key(path, "axis"), "is required for an angle check");
  for (const char* bound : {"min", "max"}) {
    if (!j.contains(bound)) continue;
    const std::string bp = key(path, bound);
    const json& v = j[bound];
    const bool isMin = std::string(bound) == "min";
    if (c.kind == CheckKind::Position) {
      if (!v.is_array() || v.size() != 3) fail(bp, "must be [x, y, z] (null: no bound)");
      for (size_t i = 0; i < 3; ++i) {
        if (v[i].is_null()) continue;
        (isMin ? c.minVec : c.maxVec)[i] = number(v[i], index(bp, i));
      }
    } else {
      (isMin ? c.min : c.max) = number(v, bp);
    }
  }
  if (!j.contains("min") && !j.contains("max")) fail(path, "needs a min or a max");
  return c;
}

}  // namespace

int Scene::steps() const {
  return std::max(1, static_cast<int>(std::llround(duration / dt)));
}

json parseJson(const std::string& text, const std::string& origin) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    const auto at = what.find("parse error");
    throw Error(origin, "invalid JSON: " + (at == std::string::npos ? what : what.substr(at)));
  } catch (const json::exception& e) {  // e.g. a number out of range
    std::string what = e.what();
    const auto at = what.find("] ");
    throw Error(origin, "invalid JSON: " + (at == std::string::npos ? what : what.substr(at + 2)));
  }
}

json readJsonFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path, "is a directory, not a " + what);
  if (!std::filesystem::exists(path, ec)) throw Error(path, "no such " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot open " + what);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(path, "cannot read " + what);
  return parseJson(ss.str(), path);
}

json readSceneFile(const std::string& path) {
  return readJsonFile(path, "scene file");
}

void applyOverride(json& doc, const std::string& keyValue) {
  const auto eq = keyValue.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw Error("--set " + keyValue, "expected KEY=VALUE, e.g. world.substeps=8");
  }
  const std::string k = keyValue.substr(0, eq), text = keyValue.substr(eq + 1);
  const std::string where = "--set " + k;
  // Split a.b[2].c or a.b.2.c into tokens.
  std::vector<std::string> tokens;
  std::string cur;
  for (size_t i = 0; i < k.size(); ++i) {
    const char c = k[i];
    if (c == '.' || c == '[' || c == ']') {
      if (!cur.empty()) tokens.push_back(cur);
      cur.clear();
      if (c == ']' && i + 1 < k.size() && k[i + 1] != '.' && k[i + 1] != '[') {
        throw Error(where, "malformed key");
      }
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) tokens.push_back(cur);
  if (tokens.empty()) throw Error(where, "empty key");
  json value;
  try {
    value = json::parse(text);
  } catch (const json::parse_error&) {
    value = text;  // a bare word: a string
  } catch (const json::exception&) {
    throw Error(where, "value out of range: " + text);
  }
  json* node = &doc;
  std::string path;
  for (size_t t = 0; t < tokens.size(); ++t) {
    const std::string& tok = tokens[t];
    const bool last = t + 1 == tokens.size();
    if (node->is_array()) {
      const bool digits =
          std::all_of(tok.begin(), tok.end(), [](char c) { return c >= '0' && c <= '9'; });
      if (!digits || tok.size() > 9)
        throw Error(where, path + " is an array: expected an index, got \"" + tok + "\"");
      const size_t i = std::stoul(tok);
      if (i >= node->size()) {
        throw Error(where,
                    path + " has " + std::to_string(node->size()) + " elements, no index " + tok);
      }
      path = index(path, i);
      node = &(*node)[i];
    } else if (node->is_object()) {
      // Missing objects on the way are created (the parser refuses keys it does not know).
      path = key(path, tok);
      if (!last && !node->contains(tok)) (*node)[tok] = json::object();
      node = &(*node)[tok];
    } else {
      throw Error(where,
                  (path.empty() ? std::string("the scene") : path) + " is not an object or array");
    }
  }
  *node = value;
}

Scene parseScene(const json& doc) {
  return parseScene(doc, builtinBaseDir());
}

Scene parseScene(const json& doc, const std::string& baseDir) {
  Scene s;
  s.baseDir = baseDir;
  object(doc, "",
         {"grip_scene", "name", "description", "world", "materials", "bodies", "joints",
          "interaction", "hands", "duration", "seed", "checks"});
  const json& version = required(doc, "", "grip_scene");
  if (!version.is_number_integer() || version.get<int64_t>() != kSceneVersion) {
    fail("grip_scene", "unsupported version " + version.dump() + " (this grip reads version " +
                           std::to_string(kSceneVersion) + ")");
  }
  s.source = doc;
  s.name = "scene";
  opt(doc, "", "name", [&](const json& v, const std::string& p) { s.name = string(v, p); });
  opt(doc, "", "description",
      [&](const json& v, const std::string& p) { s.description = string(v, p); });
  opt(doc, "", "world", [&](const json& v, const std::string& p) { parseWorld(v, p, s); });
  s.duration = positive(required(doc, "", "duration"), "duration");
  if (s.duration > 24 * 3600.0) fail("duration", "must be at most a day");
  if (s.duration / s.dt > 1e9) fail("duration", "needs more than 1e9 steps");
  opt(doc, "", "seed", [&](const json& v, const std::string& p) {
    if (!v.is_number_integer() || (!v.is_number_unsigned() && v.get<int64_t>() < 0)) {
      fail(p, "must be a non-negative integer (got " + v.dump() + ")");
    }
    s.seed = v.get<uint64_t>();
  });
  std::map<std::string, MaterialDef> materials;
  opt(doc, "", "materials", [&](const json& v, const std::string& p) {
    if (!v.is_object()) fail(p, "must be an object of named materials");
    for (auto it = v.begin(); it != v.end(); ++it) {
      materials[it.key()] = parseMaterial(it.value(), key(p, it.key()), MaterialDef{});
    }
  });
  const json& bodies = required(doc, "", "bodies");
  if (!bodies.is_array()) fail("bodies", "must be an array");
  std::set<std::string> names;
  for (size_t i = 0; i < bodies.size(); ++i) {
    const std::string p = index("bodies", i);
    s.bodies.push_back(parseBody(bodies[i], p, i, materials, s.baseDir));
    if (!names.insert(s.bodies.back().def.name).second) {
      fail(key(p, "name"), "duplicate body name \"" + s.bodies.back().def.name + "\"");
    }
  }
  opt(doc, "", "joints", [&](const json& v, const std::string& p) {
    if (!v.is_array()) fail(p, "must be an array");
    for (size_t i = 0; i < v.size(); ++i) s.joints.push_back(parseJoint(v[i], index(p, i), s));
  });
  opt(doc, "", "interaction",
      [&](const json& v, const std::string& p) { parseInteraction(v, p, s.interaction); });
  opt(doc, "", "hands", [&](const json& v, const std::string& p) {
    if (!v.is_array()) fail(p, "must be an array");
    std::set<std::string> handNames;
    for (size_t i = 0; i < v.size(); ++i) {
      s.hands.push_back(parseHand(v[i], index(p, i), i, s.baseDir));
      if (!handNames.insert(s.hands.back().def.name).second) {
        fail(key(index(p, i), "name"), "duplicate hand name \"" + s.hands.back().def.name + "\"");
      }
    }
  });
  opt(doc, "", "checks", [&](const json& v, const std::string& p) {
    if (!v.is_array()) fail(p, "must be an array");
    for (size_t i = 0; i < v.size(); ++i) s.checks.push_back(parseCheck(v[i], index(p, i), s));
  });
  return s;
}

}  // namespace grip::scene
