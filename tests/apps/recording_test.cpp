// The recording reader: a recording written by run() reads back complete, and every kind of
// damage is refused with a message naming the line and the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "scene/recording.hpp"
#include "scene/scene.hpp"

namespace grip::scene {
namespace {

namespace fs = std::filesystem;

// The lines of a short grasp_lift recording (every 10th frame), written once.
const std::vector<std::string>& recordedLines() {
  static const std::vector<std::string> lines = [] {
    // ctest runs each test in its own process, several at once: a folder of this process's.
    const fs::path dir =
        fs::temp_directory_path() / ("grip_recording_test_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    RunOptions opt;
    opt.outDir = dir.string();
    opt.recordEvery = 10;
    run(parseScene(*builtinScene("grasp_lift")), opt);
    std::ifstream in(dir / "recording.jsonl");
    std::vector<std::string> out;
    for (std::string l; std::getline(in, l);) out.push_back(l);
    fs::remove_all(dir);
    return out;
  }();
  return lines;
}

RecordingSummary check(const std::vector<std::string>& lines) {
  std::ostringstream s;
  for (const auto& l : lines) s << l << '\n';
  std::istringstream in(s.str());
  return checkRecording(in, "rec");
}

std::string errorOf(const std::vector<std::string>& lines) {
  try {
    check(lines);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(Recording, AWrittenRecordingReadsBackComplete) {
  const Scene s = parseScene(*builtinScene("grasp_lift"));
  const RecordingSummary r = check(recordedLines());
  EXPECT_EQ(r.scene, "grasp_lift");
  EXPECT_EQ(r.steps, s.steps());
  EXPECT_EQ(r.recordEvery, 10);
  EXPECT_EQ(r.frames, (s.steps() + 9) / 10);
  EXPECT_EQ(r.bodies, 2);
  EXPECT_EQ(r.hands, 1);
  EXPECT_GT(r.contacts, 10);  // the pinch holds the cube most of the run
  EXPECT_EQ(r.stateHash.size(), 16u);
}

TEST(Recording, DamageIsRefusedNamingTheLine) {
  auto lines = recordedLines();
  const size_t n = lines.size();
  const std::string last = std::to_string(n);

  auto truncated = lines;
  truncated.pop_back();
  EXPECT_EQ(errorOf(truncated),
            "rec: truncated: no end line after " + std::to_string(n - 1) + " lines");

  auto extra = lines;
  extra.push_back(lines[1]);
  EXPECT_EQ(errorOf(extra),
            "rec:" + std::to_string(n + 1) + ": unexpected line after the end line");

  auto swapped = lines;
  std::swap(swapped[1], swapped[2]);
  EXPECT_EQ(errorOf(swapped), "rec:3: frame 10 is out of order");

  auto nonFinite = lines;
  nonFinite[2] = replaced(nonFinite[2], "\"bodies\":[[", "\"bodies\":[[null,");
  EXPECT_EQ(errorOf(nonFinite), "rec:3: bodies[0] must be an array of 7 numbers");

  auto cut = lines;
  cut[2] = cut[2].substr(0, cut[2].size() / 2);
  EXPECT_EQ(errorOf(cut), "rec:3: malformed JSON");

  auto header = lines;
  header[0] = replaced(header[0], "grip-recording", "other");
  EXPECT_EQ(errorOf(header), "rec:1: not a grip recording");

  auto count = lines;
  count.back() = replaced(count.back(), "\"frames\":", "\"frames\":1");
  EXPECT_NE(errorOf(count).find("rec:" + last + ": the end line counts"), std::string::npos);

  EXPECT_EQ(errorOf({}), "rec: empty recording");
}

}  // namespace
}  // namespace grip::scene
