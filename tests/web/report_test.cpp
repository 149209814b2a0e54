// The report page and the recording checks of `grip view` (apps/web/report.hpp), and the
// hull/compound geometry of recording headers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "scene/scene.hpp"
#include "web/report.hpp"

namespace grip::web {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("grip_web_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

scene::RunResult runScene(json doc, const fs::path& dir) {
  scene::RunOptions opt;
  opt.outDir = dir.string();
  return scene::run(scene::parseScene(doc), opt);
}

// The embedded recording of a report page, as JSON lines.
std::vector<json> embedded(const std::string& page) {
  const std::string open = "<script type=\"application/x-grip-recording\" id=\"grip-recording\">\n";
  const size_t a = page.find(open);
  EXPECT_NE(a, std::string::npos);
  const size_t b = page.find("</script>", a);
  std::istringstream in(page.substr(a + open.size(), b - a - open.size()));
  std::vector<json> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(json::parse(line));
  return lines;
}

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

std::string expectError(const std::string& path) {
  try {
    checkRecording(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Report, ThinsA240HzRunTo60FramesPerSecondEndingOnTheFinalState) {
  const fs::path dir = freshDir("thin");
  json doc = *scene::builtinScene("grasp_lift");
  scene::applyOverride(doc, "world.hz=240");
  const scene::RunResult r = runScene(doc, dir);
  ReportStats st;
  const std::string page = reportHtml(r.recordingPath, r.metrics, {}, &st);
  EXPECT_EQ(st.framesIn, 600);
  EXPECT_EQ(st.keepEvery, 4);
  EXPECT_EQ(st.framesKept, 151);  // frames 1, 5, ..., 597 and the last, 600
  const std::vector<json> lines = embedded(page);
  ASSERT_EQ(lines.size(), 153u);
  EXPECT_EQ(lines[0]["recordEvery"], 4);
  EXPECT_EQ(lines[0]["report"]["sourceFrames"], 600);
  EXPECT_EQ(lines[1]["frame"], 1);
  EXPECT_EQ(lines[2]["frame"], 5);
  EXPECT_EQ(lines[151]["frame"], 600);
  EXPECT_EQ(lines[152]["end"], true);
  EXPECT_EQ(lines[152]["frames"], 151);
  // Poses rounded to 1 um: the final cube position within 0.5 um of the run's.
  const double y = r.metrics["bodies"][1]["position"][1].get<double>();
  EXPECT_NEAR(lines[151]["bodies"][1][1].get<double>(), y, 0.5e-6);
  EXPECT_NE(lines[151]["bodies"][1][1].get<double>(), y);  // rounded, not copied
  // The key frame is the one with the largest total contact force.
  double best = -1.0;
  int bestFrame = 0;
  std::ifstream in(r.recordingPath);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const json f = json::parse(line);
    if (f.contains("end")) break;
    double sum = 0.0;
    for (const json& c : f["contacts"])
      if (c["state"] != "touch")
        sum += std::hypot(c["force"][0].get<double>(), c["force"][1].get<double>(),
                          c["force"][2].get<double>());
    if (sum > best) best = sum, bestFrame = f["frame"].get<int>();
  }
  EXPECT_EQ(st.keyFrame, bestFrame);
  EXPECT_NE(page.find("Frame " + std::to_string(bestFrame) + " (t = "), std::string::npos);
  // A 60 Hz run keeps every frame.
  const scene::RunResult slow = runScene(*scene::builtinScene("grasp_lift"), freshDir("slow"));
  reportHtml(slow.recordingPath, slow.metrics, {}, &st);
  EXPECT_EQ(st.keepEvery, 1);
  EXPECT_EQ(st.framesKept, st.framesIn);
}

TEST(Report, ShowsChecksAndMetricsAndEscapesNames) {
  const fs::path dir = freshDir("escape");
  json doc = *scene::builtinScene("grasp_lift");
  doc["name"] = "a</script><b>";
  doc["checks"][0]["label"] = "x < y & </script>";
  doc["checks"][0]["max"][1] = 0.0;  // make the first check fail
  const scene::RunResult r = runScene(doc, dir);
  const std::string page = reportHtml(r.recordingPath, r.metrics);
  EXPECT_NE(page.find("<h1>a&lt;/script&gt;&lt;b&gt;: report</h1>"), std::string::npos);
  EXPECT_NE(page.find("<td class=\"fail\">FAIL</td><td>x &lt; y &amp; &lt;/script&gt;</td>"),
            std::string::npos);
  EXPECT_NE(page.find("<td class=\"pass\">PASS</td>"), std::string::npos);
  EXPECT_NE(page.find(r.metrics["stateHash"].get<std::string>()), std::string::npos);
  // Inside the embedded data no "</script" ends the element early: the first one after it
  // comes after the end line, and the name reads back.
  const std::vector<json> lines = embedded(page);
  ASSERT_EQ(lines.size(), static_cast<size_t>(r.steps) + 2);
  EXPECT_EQ(lines.back()["end"], true);
  EXPECT_EQ(lines[0]["scene"], "a</script><b>");
  // The viewer page is there, its marker replaced.
  EXPECT_NE(page.find("gripViewer"), std::string::npos);
  EXPECT_EQ(page.find("<!--GRIP-REPORT-->"), std::string::npos);
}

TEST(Report, RefusesBrokenRecordings) {
  const fs::path dir = freshDir("broken");
  const scene::RunResult r = runScene(*scene::builtinScene("push_box"), dir);
  EXPECT_NO_THROW(checkRecording(r.recordingPath));
  std::ifstream in(r.recordingPath);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string firstLine = text.substr(0, text.find('\n'));

  writeFile(dir / "cut.jsonl", text.substr(0, text.size() / 2));
  EXPECT_EQ(expectError((dir / "cut.jsonl").string()),
            (dir / "cut.jsonl").string() + ": truncated recording (no end line)");
  writeFile(dir / "empty.jsonl", "");
  EXPECT_EQ(expectError((dir / "empty.jsonl").string()),
            (dir / "empty.jsonl").string() + ": the recording is empty");
  writeFile(dir / "text.jsonl", "hello\n");
  EXPECT_EQ(expectError((dir / "text.jsonl").string()),
            (dir / "text.jsonl").string() + ": not a grip recording (line 1 is not JSON)");
  writeFile(dir / "other.jsonl", "{\"format\": \"csv\"}\n");
  EXPECT_NE(expectError((dir / "other.jsonl").string()).find("not a grip recording"),
            std::string::npos);
  std::string v9 = firstLine;
  v9.replace(v9.find("\"version\":2"), 11, "\"version\":9");
  writeFile(dir / "v9.jsonl", v9 + "\n");
  EXPECT_EQ(expectError((dir / "v9.jsonl").string()),
            (dir / "v9.jsonl").string() + ": unsupported recording version 9");
  EXPECT_NE(expectError((dir / "missing.jsonl").string()).find("cannot open"), std::string::npos);
  EXPECT_EQ(expectError(dir.string()), dir.string() + ": is a directory");
  // The report refuses a recording with a broken line, naming it.
  std::string broken = text;
  broken.insert(broken.find('\n') + 1, "{oops\n");
  writeFile(dir / "broken.jsonl", broken);
  try {
    reportHtml((dir / "broken.jsonl").string(), r.metrics);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "broken.jsonl").string() + ": line 2: invalid JSON");
  }
}

TEST(Report, StillDrawsEveryBodyAndContact) {
  const json header = {
      {"bodies",
       {{{"type", "static"}, {"shape", {{"type", "plane"}, {"normal", {0, 1, 0}}, {"offset", 0}}}},
        {{"type", "dynamic"}, {"shape", {{"type", "box"}, {"halfExtents", {0.1, 0.1, 0.1}}}}},
        {{"type", "dynamic"}, {"shape", {{"type", "sphere"}, {"radius", 0.1}}}},
        {{"type", "dynamic"},
         {"shape", {{"type", "capsule"}, {"radius", 0.05}, {"halfHeight", 0.1}}}}}},
      {"hands", json::array()}};
  const json frame = {{"frame", 1},
                      {"bodies",
                       {{0, 0, 0, 1, 0, 0, 0},
                        {0, 0.1, 0, 1, 0, 0, 0},
                        {0.4, 0.1, 0, 1, 0, 0, 0},
                        {-0.4, 0.15, 0, 1, 0, 0, 0}}},
                      {"hands", json::array()},
                      {"contacts",
                       {{{"hand", 0},
                         {"bone", 0},
                         {"body", 1},
                         {"point", {0.1, 0.1, 0}},
                         {"normal", {1, 0, 0}},
                         {"force", {-2, 0, 0}},
                         {"state", "stick"}}}}};
  const std::string svg = frameSvg(header, frame);
  auto count = [&](const std::string& what) {
    const std::regex re(what);
    return std::distance(std::sregex_iterator(svg.begin(), svg.end(), re), std::sregex_iterator());
  };
  EXPECT_EQ(count("<polygon"), 1 + 3);  // the floor and the three faces of the box in view
  EXPECT_EQ(count("<circle"), 1 + 1);   // the sphere and the contact point
  EXPECT_EQ(count("stroke-linecap=\"round\""), 1);        // the capsule
  EXPECT_EQ(count("marker-end=\"url\\(#arrow\\)\""), 1);  // the contact force
  EXPECT_EQ(count("fill=\"#2ca02c\""), 1);                // stick is green
}

TEST(Report, StillDrawsCompoundsChildByChild) {
  const json box = {{"type", "box"}, {"halfExtents", {0.05, 0.05, 0.05}}};
  const json header = {
      {"bodies",
       {{{"type", "dynamic"},
         {"shape",
          {{"type", "compound"},
           {"children",
            {{{"position", {0, 0, 0}}, {"orientation", {1, 0, 0, 0}}, {"shape", box}},
             {{"position", {0.3, 0, 0}}, {"orientation", {1, 0, 0, 0}}, {"shape", box}}}}}}}}},
      {"hands", json::array()}};
  const json frame = {{"frame", 1},
                      {"bodies", {{0, 0.05, 0, 1, 0, 0, 0}}},
                      {"hands", json::array()},
                      {"contacts", json::array()}};
  const std::string svg = frameSvg(header, frame);
  size_t n = 0;
  for (size_t at = svg.find("<polygon"); at != std::string::npos; at = svg.find("<polygon", at + 1))
    ++n;
  EXPECT_EQ(n, 6u);  // three faces in view of each of the two boxes
}

TEST(Report, HeadersCarryHullAndCompoundGeometry) {
  const ShapePtr hull = Shape::convexHull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const json h = scene::shapeJson(*hull);
  EXPECT_EQ(h["type"], "hull");
  EXPECT_EQ(h["points"].size(), 4u);
  EXPECT_EQ(h["faces"].size(), 4u);
  for (const json& f : h["faces"]) EXPECT_EQ(f.size(), 3u);
  Transform at;
  at.p = Vec3(0.5, 0, 0);
  const ShapePtr c = Shape::compound({{Shape::box({0.1, 0.2, 0.3}), Transform{}}, {hull, at}});
  const json j = scene::shapeJson(*c);
  EXPECT_EQ(j["type"], "compound");
  ASSERT_EQ(j["children"].size(), 2u);
  EXPECT_EQ(j["children"][0]["shape"]["halfExtents"], json({0.1, 0.2, 0.3}));
  EXPECT_EQ(j["children"][1]["position"], json({0.5, 0.0, 0.0}));
  EXPECT_EQ(j["children"][1]["orientation"], json({1.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(j["children"][1]["shape"]["type"], "hull");
}

}  // namespace
}  // namespace grip::web
