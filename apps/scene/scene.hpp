// Scene files for `grip run`: a versioned JSON description of a world, its bodies, scripted
// hands and the interaction method, plus the checks of its expected outcome. Parsing validates
// everything and throws grip::Error whose field is the JSON path of the bad value, e.g.
// "bodies[2].shape.halfExtents[1]: must be positive". See docs/scenes.md for the format.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "collision/asset.hpp"
#include "interaction/interaction.hpp"

namespace grip::scene {

inline constexpr int kSceneVersion = 1;
// Version 2 of the recording adds the geometry of hulls (points, faces) and compounds
// (children) to the header's shapes, so that a viewer can draw every body.
inline constexpr int kRecordingVersion = 2;

// ---- the parsed scene -------------------------------------------------------------------------

struct BodySpec {
  BodyDef def;
  std::optional<BodyInteractionDef> interaction;  // per-body hand settings
  std::string asset;  // the runtime asset file of an asset or mesh shape (resolved), else empty
};

// A bone pressed into a surface (interaction/scenarios.hpp pressBone).
struct BonePress {
  int bone = 0;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitY();
  Vec3 axis = Vec3::UnitZ();
  double depth = 0.0;
};

// Thumb and index tips squeezing the x faces of an axis-aligned cube (scenarios::pinchCube).
struct PinchSpec {
  Vec3 center = Vec3::Zero();
  double halfWidth = 0.0;
  double depth = 0.0;
};

struct KeySpec {
  double time = 0.0;
  std::optional<Transform> palm;  // a posed hand: palm frame + grasp pose
  GraspPose pose = GraspPose::Open;
  // Otherwise the hand is parked here (default: 10 m above the pinch centre or the mean pressed
  // point, so that the palm moves with the fingers), then pinch/press bones are placed.
  std::optional<Vec3> park;
  std::optional<PinchSpec> pinch;
  std::vector<BonePress> press;
  bool tracked = true;
};

struct HandSpec {
  HandDef def;
  std::vector<KeySpec> keys;
  double positionNoise = 0.0;  // palm keyframes only (ScriptedHand)
  double rotationNoise = 0.0;
  std::vector<std::pair<double, double>> trackingLoss;
  // A hand from a recorded tracking file: frames (time, pose), converted to grip's frame.
  std::vector<std::pair<double, HandPose>> tracked;
};

// A joint between two of the scene's bodies (indices into Scene::bodies); def's ids are set
// when the world is built.
struct JointSpec {
  JointDef def;
  int a = 0, b = 0;
};
// The joint types as scene files and recordings spell them, in JointType's order.
inline constexpr std::array<const char*, 5> kJointTypeNames = {"fixed", "ball", "hinge", "slider",
                                                               "distance"};

enum class CheckKind : uint8_t { Position, Displacement, Speed, LowestHeight, HandContacts, Angle };

// An expected outcome, evaluated at the end of a run (LowestHeight: over the whole run).
struct CheckSpec {
  CheckKind kind = CheckKind::Position;
  std::string label;         // printed; defaults to a description of the check
  std::vector<int> bodies;   // indices into Scene::bodies
  int hand = -1;             // HandContacts
  std::optional<Vec3> axis;  // Displacement: project on it; Angle: rotation about it
  std::array<std::optional<double>, 3> minVec{}, maxVec{};  // Position
  std::optional<double> min, max;                           // everything else
  double since = 0.0;  // Displacement, Angle: measured from the state at this time (s)
};

struct Scene {
  std::string name;
  std::string description;
  WorldDef world;
  double dt = 1.0 / 60.0;
  double duration = 1.0;
  uint64_t seed = 1;
  InteractionDef interaction;
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  std::vector<HandSpec> hands;
  std::vector<CheckSpec> checks;
  nlohmann::json source;  // the document it was parsed from (after overrides)
  std::string baseDir;    // relative file paths in the scene are taken from here
  int steps() const;
};

// ---- loading ------------------------------------------------------------------------------------

// JSON text -> document. Throws grip::Error("<origin>", "invalid JSON: ...").
nlohmann::json parseJson(const std::string& text, const std::string& origin);
// Reads a JSON file (throws grip::Error naming the path when it cannot be read or parsed; `what`
// names the kind of file in the message).
nlohmann::json readJsonFile(const std::string& path, const std::string& what);
nlohmann::json readSceneFile(const std::string& path);
// "KEY=VALUE": KEY is a path such as world.substeps, bodies[1].mass or bodies.1.mass; VALUE is
// JSON (8, true, [0,1,0], "box") or else taken as a string. Intermediate objects must exist.
void applyOverride(nlohmann::json& doc, const std::string& keyValue);
// A recorded tracking file's document -> frames (docs/scenes.md, "Tracking files"); errors name
// the JSON path inside the file.
std::vector<std::pair<double, HandPose>> parseTracking(const nlohmann::json& doc);

// Validates a document and builds the scene. Relative paths (assets, meshes, tracking files) are
// taken from `baseDir`: the scene file's folder; for built-in scenes and by default the grip
// source tree (builtinBaseDir()).
Scene parseScene(const nlohmann::json& doc, const std::string& baseDir);
Scene parseScene(const nlohmann::json& doc);

// ---- files a scene refers to (detail/assets.cpp) ------------------------------------------------

std::string builtinBaseDir();
std::string resolvePath(const std::string& baseDir, const std::string& path);
bool haveVoxelModule();
// The asset cache: $GRIP_CACHE_DIR, else $XDG_CACHE_HOME/grip, else ~/.cache/grip.
std::string assetCacheDir();
// Prepares a mesh (OFF/OBJ/STL/PLY) into a runtime asset at a level of detail and density, or
// finds it in the cache (keyed by the mesh's bytes and the options); returns the asset's path.
// Without the voxel module: throws grip::Error saying so.
std::string preparedMeshAsset(const std::string& meshPath, const std::string& lod, double density);

// ---- built-in scenes ----------------------------------------------------------------------------

struct BuiltinScene {
  std::string name;
  std::string summary;
  nlohmann::json (*make)();
};
const std::vector<BuiltinScene>& builtinScenes();
std::optional<nlohmann::json> builtinScene(const std::string& name);

// ---- running ------------------------------------------------------------------------------------

// Hand poses at increasing times -> the pose at t: each bone interpolated between the keys around
// t (position linearly, orientation by slerp), held before the first and after the last key. A
// bone that moves farther than `jump` (m) between two keys (a parked bone being placed) switches
// at the later key instead of sweeping through the scene; an untracked key is held until the
// next one.
using PoseKeys = std::vector<std::pair<double, HandPose>>;
HandPose samplePoses(const PoseKeys& keys, double t, double jump = 0.5);

struct CheckResult {
  std::string label;
  bool passed = false;
  std::string detail;  // the measured value against the bound
};

struct RunOptions {
  std::string outDir;                                 // empty: no recording or metrics files
  int recordEvery = 1;                                // record every n-th frame
  std::function<void(int step, int steps)> progress;  // called now and then
};

struct RunResult {
  uint64_t stateHash = 0;
  int steps = 0;
  double simulatedTime = 0.0;
  double wallSeconds = 0.0;
  std::vector<CheckResult> checks;
  bool allPassed() const;
  nlohmann::json metrics;
  std::string recordingPath, metricsPath;  // empty when not written
};

// A shape as the recording's header describes it (docs/scenes.md).
nlohmann::json shapeJson(const Shape& shape);

// Runs the scene to its duration. Throws grip::Error on failures to write the output (the
// partial recording is removed; nothing is left looking complete).
RunResult run(const Scene& scene, const RunOptions& options = {});

}  // namespace grip::scene
