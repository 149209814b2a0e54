// The recording reader: one line at a time (a long recording is never held in memory), every
// field checked against the header.
#include "scene/recording.hpp"

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "interaction/hand.hpp"
#include "scene/scene.hpp"

namespace grip::scene {

using nlohmann::json;

namespace {

class LineChecker {
 public:
  explicit LineChecker(std::string where) : where_(std::move(where)) {}
  [[noreturn]] void fail(const std::string& what) const { throw Error(where_, what); }

  const json& field(const json& obj, const char* name) const {
    if (!obj.is_object()) fail("expected an object");
    const auto it = obj.find(name);
    if (it == obj.end()) fail(std::string("missing \"") + name + "\"");
    return *it;
  }
  const json& array(const json& obj, const char* name) const {
    const json& a = field(obj, name);
    if (!a.is_array()) fail(std::string("\"") + name + "\" must be an array");
    return a;
  }
  std::string string(const json& obj, const char* name) const {
    const json& s = field(obj, name);
    if (!s.is_string()) fail(std::string("\"") + name + "\" must be a string");
    return s.get<std::string>();
  }
  double number(const json& obj, const char* name) const {
    const json& x = field(obj, name);
    if (!x.is_number()) fail(std::string("\"") + name + "\" must be a number");
    const double v = x.get<double>();
    if (!std::isfinite(v)) fail(std::string("\"") + name + "\" must be finite");
    return v;
  }
  // A non-negative integer below `limit`.
  int index(const json& obj, const char* name, int64_t limit) const {
    const json& x = field(obj, name);
    if (!x.is_number_integer() || x.get<int64_t>() < 0 || x.get<int64_t>() >= limit)
      fail(std::string("\"") + name + "\" must be an integer in [0, " + std::to_string(limit) +
           ")");
    return static_cast<int>(x.get<int64_t>());
  }
  // n finite numbers (a pose is 7: position, quaternion w x y z; a vector 3).
  void numbers(const json& a, size_t n, const std::string& what) const {
    if (!a.is_array() || a.size() != n)
      fail(what + " must be an array of " + std::to_string(n) + " numbers");
    for (const json& x : a)
      if (!x.is_number() || !std::isfinite(x.get<double>()))
        fail(what + " must hold finite numbers (null is a non-finite value)");
  }
  void poses(const json& a, size_t n, const std::string& what) const {
    if (!a.is_array() || a.size() != n)
      fail(what + " must hold " + std::to_string(n) + " poses (got " +
           (a.is_array() ? std::to_string(a.size()) : std::string(a.type_name())) + ")");
    for (size_t i = 0; i < n; ++i) numbers(a[i], 7, what + "[" + std::to_string(i) + "]");
  }

 private:
  std::string where_;
};

}  // namespace

RecordingSummary checkRecording(std::istream& in, const std::string& origin) {
  RecordingSummary sum;
  std::string text;
  size_t lineNo = 0;
  bool ended = false;
  int lastFrame = 0;
  while (std::getline(in, text)) {
    ++lineNo;
    const LineChecker c(origin + ":" + std::to_string(lineNo));
    if (ended) c.fail("unexpected line after the end line");
    const json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) c.fail("malformed JSON");
    if (!j.is_object()) c.fail("expected an object");
    if (lineNo == 1) {
      if (c.string(j, "format") != "grip-recording") c.fail("not a grip recording");
      const double version = c.number(j, "version");
      if (version != 1.0 && version != kRecordingVersion)  // 2 only added geometry to the header
        c.fail("unsupported version (this build reads 1 to " + std::to_string(kRecordingVersion) +
               ")");
      sum.scene = c.string(j, "scene");
      sum.dt = c.number(j, "dt");
      if (!(sum.dt > 0.0)) c.fail("\"dt\" must be positive");
      sum.steps = c.index(j, "steps", int64_t{1} << 31);
      sum.recordEvery = c.index(j, "recordEvery", int64_t{1} << 31);
      if (sum.recordEvery < 1) c.fail("\"recordEvery\" must be at least 1");
      const json& bodies = c.array(j, "bodies");
      for (const json& b : bodies) c.string(b, "name"), c.field(b, "shape");
      const json& hands = c.array(j, "hands");
      for (const json& h : hands)
        if (c.array(h, "bones").size() != static_cast<size_t>(kBonesPerHand))
          c.fail("a hand must have " + std::to_string(kBonesPerHand) + " bones");
      sum.bodies = static_cast<int>(bodies.size());
      sum.hands = static_cast<int>(hands.size());
      continue;
    }
    if (j.contains("end")) {
      if (c.field(j, "end") != true) c.fail("\"end\" must be true");
      if (c.index(j, "frames", int64_t{1} << 31) != sum.frames)
        c.fail("the end line counts " + j["frames"].dump() + " frames, the file has " +
               std::to_string(sum.frames));
      sum.stateHash = c.string(j, "stateHash");
      ended = true;
      continue;
    }
    const int frame = c.index(j, "frame", int64_t{sum.steps} + 1);
    if (frame <= lastFrame) c.fail("frame " + std::to_string(frame) + " is out of order");
    lastFrame = frame;
    c.number(j, "t");
    c.poses(c.array(j, "bodies"), static_cast<size_t>(sum.bodies), "bodies");
    const json& hands = c.array(j, "hands");
    if (hands.size() != static_cast<size_t>(sum.hands))
      c.fail("\"hands\" must hold " + std::to_string(sum.hands) + " hands");
    for (const json& h : hands) {
      if (!c.field(h, "tracked").is_boolean()) c.fail("\"tracked\" must be true or false");
      c.poses(c.array(h, "bones"), kBonesPerHand, "bones");
      c.poses(c.array(h, "visual"), kBonesPerHand, "visual");
    }
    for (const json& k : c.array(j, "contacts")) {
      c.index(k, "hand", sum.hands);
      c.index(k, "bone", kBonesPerHand);
      c.index(k, "body", sum.bodies);
      for (const char* v : {"point", "normal", "force"}) c.numbers(c.field(k, v), 3, v);
      const std::string state = c.string(k, "state");
      if (state != "stick" && state != "slip" && state != "touch")
        c.fail("\"state\" must be stick, slip or touch (got \"" + state + "\")");
      ++sum.contacts;
    }
    ++sum.frames;
  }
  if (lineNo == 0) throw Error(origin, "empty recording");
  if (!ended)
    throw Error(origin, "truncated: no end line after " + std::to_string(lineNo) + " lines");
  return sum;
}

RecordingSummary checkRecordingFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot open the recording");
  return checkRecording(in, path);
}

}  // namespace grip::scene
