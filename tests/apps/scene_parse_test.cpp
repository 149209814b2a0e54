// Scene files: valid documents parse into the engine's defs; invalid ones are refused with the
// JSON path of the bad value; --set overrides edit the document by path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene/scene.hpp"

namespace grip::scene {
namespace {

using nlohmann::json;

json minimal() {
  return json::parse(R"({
    "grip_scene": 1,
    "name": "t",
    "duration": 0.5,
    "world": {"gravity": [0, -9.81, 0], "hz": 120, "substeps": 2, "iterations": 1},
    "materials": {"wood": {"staticFriction": 0.4, "dynamicFriction": 0.3, "density": 600}},
    "bodies": [
      {"name": "floor", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
      {"name": "a", "shape": {"type": "box", "halfExtents": [0.1, 0.2, 0.3]}, "position": [0, 1, 0],
       "orientation": {"axis": [0, 1, 0], "degrees": 90}, "material": "wood"},
      {"name": "b", "shape": {"type": "sphere", "radius": 0.1}, "mass": 2, "linearVelocity": [1, 0, 0],
       "filter": {"category": [2], "mask": [0, 2, 63], "group": -4}},
      {"name": "c", "shape": {"type": "capsule", "radius": 0.05, "halfHeight": 0.1}, "orientation": [1, 0, 0, 0]},
      {"name": "d", "shape": {"type": "hull", "points": [[0,0,0],[0.1,0,0],[0,0.1,0],[0,0,0.1]]}}
    ],
    "joints": [{"type": "hinge", "a": "floor", "b": "a", "anchor": [0, 1, 0.3], "axis": [0, 0, 2],
                "limit": [-1, 0.5], "motor": {"speed": 0.5, "maxForce": 2}},
               {"type": "ball", "a": "b", "b": "c", "anchor": [0, 0, 0], "collideConnected": true,
                "breakForce": 50, "breakTorque": 5, "cone": 0.4},
               {"type": "slider", "a": "floor", "b": "d", "anchor": [0, 0, 0],
                "spring": {"hertz": 2, "dampingRatio": 0.5, "target": 0.1}},
               {"type": "distance", "a": "a", "b": "d", "anchor": [0, 1, 0], "anchorB": [0, 0, 0],
                "limit": [-1, 0]}],
    "interaction": {"method": "kinematic", "gamma": 500, "patchSamples": 5, "touchable": [0, 3]},
    "hands": [{"name": "h", "side": "left", "keyframes": [
      {"time": 0, "palm": {"position": [0, 0.5, 0]}, "pose": "pinch"},
      {"time": 1, "palm": {"position": [0, 0.6, 0]}, "pose": "open"}]}],
    "checks": [{"kind": "speed", "body": "b", "max": 10}]
  })");
}

// The message of the error parsing `doc` throws ("" when it parses).
std::string errorOf(const json& doc) {
  try {
    parseScene(doc);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SceneParse, AValidSceneFillsTheDefs) {
  const Scene s = parseScene(minimal());
  EXPECT_EQ(s.name, "t");
  EXPECT_DOUBLE_EQ(s.dt, 1.0 / 120.0);
  EXPECT_EQ(s.steps(), 60);
  EXPECT_EQ(s.world.substeps, 2);
  ASSERT_EQ(s.bodies.size(), 5u);
  EXPECT_EQ(s.bodies[0].def.type, BodyType::Static);
  EXPECT_DOUBLE_EQ(s.bodies[1].def.material.staticFriction, 0.4);
  EXPECT_DOUBLE_EQ(s.bodies[1].def.material.density, 600.0);
  EXPECT_NEAR(
      s.bodies[1].def.orientation.angularDistance(Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()))),
      0.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.bodies[2].def.mass, 2.0);
  EXPECT_EQ(s.bodies[2].def.linearVelocity, Vec3(1, 0, 0));
  EXPECT_EQ(s.bodies[2].def.filter.category, 4u);
  EXPECT_EQ(s.bodies[2].def.filter.mask, 5u | (uint64_t{1} << 63));
  EXPECT_EQ(s.bodies[2].def.filter.group, -4);
  EXPECT_EQ(s.bodies[1].def.filter.mask, ~uint64_t{0});  // the default: every kind
  ASSERT_GE(s.joints.size(), 2u);
  EXPECT_EQ(s.joints[0].def.type, JointType::Hinge);
  EXPECT_EQ(s.joints[0].a, 0);
  EXPECT_EQ(s.joints[0].b, 1);
  EXPECT_EQ(s.joints[0].def.axis, Vec3(0, 0, 1));
  EXPECT_TRUE(s.joints[0].def.enableLimit);
  EXPECT_DOUBLE_EQ(s.joints[0].def.lower, -1.0);
  EXPECT_DOUBLE_EQ(s.joints[0].def.upper, 0.5);
  EXPECT_FALSE(s.joints[0].def.collideConnected);
  EXPECT_TRUE(s.joints[0].def.enableMotor);
  EXPECT_DOUBLE_EQ(s.joints[0].def.motorSpeed, 0.5);
  EXPECT_DOUBLE_EQ(s.joints[0].def.maxMotorForce, 2.0);
  EXPECT_EQ(s.joints[1].def.type, JointType::Ball);
  EXPECT_TRUE(s.joints[1].def.collideConnected);
  EXPECT_FALSE(s.joints[1].def.enableLimit);
  EXPECT_DOUBLE_EQ(s.joints[1].def.breakForce, 50.0);
  EXPECT_DOUBLE_EQ(s.joints[1].def.breakTorque, 5.0);
  EXPECT_TRUE(s.joints[1].def.enableCone);
  EXPECT_DOUBLE_EQ(s.joints[1].def.coneAngle, 0.4);
  EXPECT_FALSE(s.joints[0].def.enableCone);
  EXPECT_TRUE(std::isinf(s.joints[0].def.breakForce));  // never, unless given
  ASSERT_EQ(s.joints.size(), 4u);
  EXPECT_EQ(s.joints[3].def.type, JointType::Distance);
  EXPECT_EQ(s.joints[3].def.anchorB, Vec3::Zero());
  EXPECT_DOUBLE_EQ(s.joints[3].def.lower, -1.0);
  EXPECT_TRUE(s.joints[2].def.enableSpring);
  EXPECT_DOUBLE_EQ(s.joints[2].def.springHertz, 2.0);
  EXPECT_DOUBLE_EQ(s.joints[2].def.springDampingRatio, 0.5);
  EXPECT_DOUBLE_EQ(s.joints[2].def.springTarget, 0.1);
  EXPECT_EQ(s.interaction.method, InteractionMethod::Kinematic);
  EXPECT_DOUBLE_EQ(s.interaction.gamma, 500.0);
  EXPECT_EQ(s.interaction.touchable.mask, 9u);
  ASSERT_EQ(s.hands.size(), 1u);
  EXPECT_EQ(s.hands[0].def.side, Handedness::Left);
  EXPECT_EQ(s.hands[0].keys[0].pose, GraspPose::Pinch);
  ASSERT_EQ(s.checks.size(), 1u);
  EXPECT_EQ(s.checks[0].bodies, std::vector<int>{2});
}

TEST(SceneParse, ErrorsNameTheJsonPath) {
  struct Case {
    std::string key, value, expected;
  };
  const std::vector<Case> cases = {
      {"bodies[1].shape.halfExtents[1]", "-1", "bodies[1].shape.halfExtents[1]: must be positive"},
      {"bodies[2].mass", "0", "bodies[2].mass: must be positive"},
      {"bodies[2].shape.radius", "\"big\"", "bodies[2].shape.radius: must be a number"},
      {"bodies[1].shape.type", "\"cone\"", "bodies[1].shape.type: must be one of box, sphere"},
      {"bodies[1].material", "\"steel\"", "bodies[1].material: unknown material \"steel\""},
      {"bodies[1].colour", "1", "bodies[1].colour: unknown field"},
      {"bodies[3].position", "[1, 2]", "bodies[3].position: must be an array of 3 numbers"},
      {"bodies[2].filter.mask[1]", "64", "bodies[2].filter.mask[1]: must be between 0 and 63"},
      {"bodies[2].filter.category", "2", "bodies[2].filter.category: must be an array of kinds"},
      {"bodies[2].filter.layer", "1", "bodies[2].filter.layer: unknown field"},
      {"bodies[2].filter.group", "0.5", "bodies[2].filter.group: must be an integer"},
      {"interaction.touchable[0]", "-1", "interaction.touchable[0]: must be between 0 and 63"},
      {"joints[0].type", "\"weld\"",
       "joints[0].type: must be one of fixed, ball, hinge, slider, distance"},
      {"joints[0].b", "\"zz\"", "joints[0].b: unknown body \"zz\""},
      {"joints[0].b", "\"floor\"", "joints[0].b: must be another body than a"},
      {"joints[0].axis", "[0, 0, 0]", "joints[0].axis: must not be the zero vector"},
      {"joints[0].limit", "[1, 0]", "joints[0].limit[0]: must not exceed upper"},
      {"joints[0].limit", "[-4, 0]", "joints[0].limit: a hinge's limits must be within [-pi, pi]"},
      {"joints[1].limit", "[0, 1]",
       "joints[1].limit: only hinges, sliders and distance joints have limits"},
      {"joints[1].anchor", "[0, 1]", "joints[1].anchor: must be an array of 3 numbers"},
      {"joints[0].cone", "0.5", "joints[0].cone: only ball joints have a cone"},
      {"joints[1].cone", "0", "joints[1].cone: must be within (0, pi) rad"},
      {"joints[1].cone", "3.5", "joints[1].cone: must be within (0, pi) rad"},
      {"joints[1].motor", "{\"maxForce\": 1}",
       "joints[1].motor: only hinges, sliders and distance joints have motors"},
      {"joints[0].motor.maxForce", "-1", "joints[0].motor.maxForce: must not be negative"},
      {"joints[0].motor.torque", "1", "joints[0].motor.torque: unknown field"},
      {"joints[1].spring", "{\"hertz\": 1}",
       "joints[1].spring: only hinges, sliders and distance joints have springs"},
      {"joints[2].spring.hertz", "0", "joints[2].spring.hertz: must be positive"},
      {"joints[2].spring.dampingRatio", "-1",
       "joints[2].spring.dampingRatio: must not be negative"},
      {"joints[2].spring.stiffness", "1", "joints[2].spring.stiffness: unknown field"},
      {"joints[1].anchorB", "[0, 1, 0]",
       "joints[1].anchorB: only distance joints have a second anchor"},
      {"joints[3].anchorB", "[0, 1, 0]",
       "joints[3].anchorB: must be apart from anchor (a distance joint's length)"},
      {"joints[1].breakForce", "0", "joints[1].breakForce: must be positive (got 0)"},
      {"joints[1].breakTorque", "\"never\"", "joints[1].breakTorque: must be a number"},
      {"world.substeps", "0", "world.substeps: must be between 1 and 1000"},
      {"world.substeps", "2.5", "world.substeps: must be an integer"},
      {"world.dt", "0.01", "world.dt: give either hz or dt"},
      {"world.contactReuseDistance", "-0.001", "world.contactReuseDistance: must not be negative"},
      {"interaction.method", "\"magic\"", "interaction.method: must be one of coulomb, kinematic"},
      {"hands[0].keyframes[1].time", "0", "hands[0].keyframes[1].time: must be later"},
      {"hands[0].keyframes[0].pose", "\"fist\"", "hands[0].keyframes[0].pose: must be one of open"},
      {"checks[0].body", "\"zz\"", "checks[0].body: unknown body \"zz\""},
      {"grip_scene", "2", "grip_scene: unsupported version 2"},
      {"duration", "-1", "duration: must be positive"},
      {"bodies[0].type", "\"dynamic\"", "bodies[0].type: a plane must be static"},
      {"materials.wood.dynamicFriction", "0.9", "materials.wood.dynamicFriction: must not exceed"},
      {"bodies[4].shape.points", "[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]", "bodies[4].shape.points:"},
  };
  for (const Case& c : cases) {
    json doc = minimal();
    applyOverride(doc, c.key + "=" + c.value);
    const std::string msg = errorOf(doc);
    EXPECT_EQ(msg.rfind(c.expected, 0), 0u) << c.key << "=" << c.value << " gave: " << msg;
  }
  json doc = minimal();
  doc.erase("duration");
  EXPECT_EQ(errorOf(doc), "duration: is required");
  doc = minimal();
  doc["bodies"][2]["name"] = "a";
  EXPECT_EQ(errorOf(doc), "bodies[2].name: duplicate body name \"a\"");
}

TEST(SceneParse, OverridesEditByPath) {
  json doc = minimal();
  applyOverride(doc, "world.substeps=8");
  applyOverride(doc, "bodies[2].mass=3.5");
  applyOverride(doc, "bodies.1.position=[0,2,0]");
  applyOverride(doc, "interaction.method=coulomb");  // a bare word is a string
  applyOverride(doc, "seed=42");                     // a new top-level field
  const Scene s = parseScene(doc);
  EXPECT_EQ(s.world.substeps, 8);
  EXPECT_DOUBLE_EQ(s.bodies[2].def.mass, 3.5);
  EXPECT_EQ(s.bodies[1].def.position, Vec3(0, 2, 0));
  EXPECT_EQ(s.interaction.method, InteractionMethod::Friction);
  EXPECT_EQ(s.seed, 42u);
}

TEST(SceneParse, BadOverridesAreRefused) {
  auto err = [](const std::string& kv) -> std::string {
    json doc = minimal();
    try {
      applyOverride(doc, kv);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(err("world.substeps"),
            "--set world.substeps: expected KEY=VALUE, e.g. world.substeps=8");
  EXPECT_EQ(err("=3"), "--set =3: expected KEY=VALUE, e.g. world.substeps=8");
  EXPECT_EQ(err("bodies[9].mass=1"), "--set bodies[9].mass: bodies has 5 elements, no index 9");
  EXPECT_EQ(err("bodies.x.mass=1"),
            "--set bodies.x.mass: bodies is an array: expected an index, got \"x\"");
  EXPECT_EQ(err("duration=1e400"), "--set duration: value out of range: 1e400");
  EXPECT_EQ(err("duration.x=1"), "--set duration.x: duration is not an object or array");
  // An unknown final key is caught by the parser, with its path.
  json doc = minimal();
  applyOverride(doc, "world.substep=8");
  EXPECT_EQ(errorOf(doc), "world.substep: unknown field");
  // Missing objects on the way are created; a made-up one is then refused by the parser.
  doc = minimal();
  applyOverride(doc, "nothing.here=1");
  EXPECT_EQ(errorOf(doc), "nothing: unknown field");
  doc = minimal();
  doc.erase("world");
  applyOverride(doc, "world.hz=240");
  EXPECT_DOUBLE_EQ(parseScene(doc).dt, 1.0 / 240.0);
}

TEST(SceneParse, InvalidJsonTextIsRefused) {
  try {
    parseJson("{\"grip_scene\": 1,", "x.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("x.json: invalid JSON: parse error", 0), 0u) << e.what();
  }
  try {
    readSceneFile("/nonexistent/scene.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/scene.json: no such scene file");
  }
  try {
    readSceneFile("/");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "/: is a directory, not a scene file");
  }
  try {
    parseJson("[1e400]", "big.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("big.json: invalid JSON: number overflow", 0), 0u)
        << e.what();
  }
}

TEST(SceneParse, EveryBuiltinSceneParses) {
  ASSERT_GE(builtinScenes().size(), 6u);
  for (const BuiltinScene& b : builtinScenes()) {
    const json doc = b.make();
    EXPECT_EQ(doc["name"], b.name);
    EXPECT_NO_THROW(parseScene(doc)) << b.name;
    // The printed document reads back to the same scene.
    const json again = parseJson(doc.dump(2), b.name);
    EXPECT_EQ(again, doc);
  }
  EXPECT_FALSE(builtinScene("no_such_scene").has_value());
}

}  // namespace
}  // namespace grip::scene
