// The work-precision sweep (apps/sweep): the quick sweep's files, and grip's error at its
// default settings against the physics bars of docs/accuracy.md. Timings are never asserted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "sweep/sweep.hpp"

using namespace grip;

namespace {

const std::vector<sweep::Sample>& quickSamples() {
  static const std::vector<sweep::Sample> s = [] {
    sweep::Options o;
    o.quick = true;
    o.repeats = 1;
    return sweep::run({sweep::gripEngine()}, o);
  }();
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ss(line);
  std::string x;
  while (std::getline(ss, x, ',')) f.push_back(x);
  if (!line.empty() && line.back() == ',') f.push_back("");
  return f;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// The tags of an XML text nest properly (a parse-level check, enough for our own writer).
bool wellNested(const std::string& x, std::string& why) {
  std::vector<std::string> open;
  for (size_t i = x.find('<'); i != std::string::npos; i = x.find('<', i + 1)) {
    const size_t end = x.find('>', i);
    if (end == std::string::npos) return why = "unterminated tag", false;
    const std::string tag = x.substr(i + 1, end - i - 1);
    if (tag.empty()) return why = "empty tag", false;
    const bool closing = tag[0] == '/', selfClosing = tag.back() == '/';
    const std::string name = tag.substr(closing, tag.find_first_of(" />", closing) - closing);
    if (closing) {
      if (open.empty() || open.back() != name) return why = "unbalanced </" + name + ">", false;
      open.pop_back();
    } else if (!selfClosing) {
      open.push_back(name);
    }
  }
  if (!open.empty()) return why = "<" + open.back() + "> never closed", false;
  return true;
}

TEST(Sweep, QuickSweepWritesTheCsvWithAHeaderAndRowsForEachScene) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "grip_sweep_test";
  std::filesystem::remove_all(dir);
  sweep::write(quickSamples(), dir.string());
  std::ifstream f(dir / "sweep.csv");
  std::string line;
  ASSERT_TRUE(std::getline(f, line));
  EXPECT_EQ(line,
            "engine,scene,dt,substeps,iterations,seconds,error,error_name,error2,error2_name,"
            "default");
  std::map<std::string, int> rows, defaults;
  while (std::getline(f, line)) {
    const std::vector<std::string> c = split(line);
    ASSERT_EQ(c.size(), 11u) << line;
    EXPECT_EQ(c[0], "grip");
    EXPECT_GT(std::stod(c[2]), 0.0) << line;
    EXPECT_GE(std::stod(c[5]), 0.0) << line;
    EXPECT_GE(std::stod(c[6]), 0.0) << line;
    EXPECT_FALSE(c[7].empty()) << line;
    ++rows[c[1]];
    defaults[c[1]] += c[10] == "1";
  }
  for (const std::string& scene : sweep::sceneNames()) {
    EXPECT_GE(rows[scene], 4) << scene;
    EXPECT_EQ(defaults[scene], 1) << scene;  // exactly one default setting per scene
  }
  EXPECT_EQ(rows.size(), sweep::sceneNames().size());
  EXPECT_EQ(slurp(dir / "sweep.svg"), sweep::svg(quickSamples()));
}

TEST(Sweep, SvgIsWellFormedWithOnePanelPerScene) {
  const std::string s = sweep::svg(quickSamples());
  ASSERT_TRUE(s.starts_with("<svg "));
  EXPECT_TRUE(s.ends_with("</svg>\n"));
  std::string why;
  EXPECT_TRUE(wellNested(s, why)) << why;
  size_t panels = 0;
  for (size_t i = s.find("class=\"panel\""); i != std::string::npos;
       i = s.find("class=\"panel\"", i + 1))
    ++panels;
  // One per scene, and one for the rotation's energy error.
  EXPECT_EQ(panels, sweep::sceneNames().size() + 1);
  for (const std::string& scene : sweep::sceneNames())
    EXPECT_NE(s.find("id=\"panel-" + scene + "\""), std::string::npos) << scene;
  EXPECT_NE(s.find("id=\"panel-rotation_energy\""), std::string::npos);
  // The Pareto front is a line per engine and panel, the default a ring.
  EXPECT_NE(s.find("<polyline"), std::string::npos);
  EXPECT_NE(s.find("r=\"6\" fill=\"none\""), std::string::npos);
}

// grip's error at its default settings (60 Hz, 4 substeps, 1 relax pass) or at the rate the
// bar names: the bars of docs/accuracy.md.
sweep::Sample atDefaults(const std::string& scene, double dt = 1.0 / 60.0) {
  const sweep::Engine e = sweep::gripEngine();
  sweep::Settings s = e.defaults;
  s.dt = dt;
  return sweep::measure(e, scene, s, /*quick=*/true);
}

TEST(Sweep, GripMeetsThePhysicsBarsAtItsDefaults) {
  EXPECT_LT(atDefaults("incline", 1.0 / 240.0).error, 0.005);  // slide within 0.5 % at 240 Hz
  EXPECT_LT(atDefaults("incline").error, 0.01);                // and within 1 % at 60 Hz
  EXPECT_LT(atDefaults("incline_stick").error, 1e-3);          // sticks: moves < 1 mm in 2 s
  const sweep::Sample stack = atDefaults("stack");
  EXPECT_LT(stack.error, 1e-3);                              // the top drifts < 1 mm over 10 s
  EXPECT_LT(stack.error2, 2e-3);                             // after settling < 2 mm
  EXPECT_LT(atDefaults("push").error, 0.005);                // travel within 0.5 %
  EXPECT_LT(atDefaults("rotation").error, 1e-9);             // grip keeps the world L exactly
  EXPECT_LT(atDefaults("bounce", 1.0 / 240.0).error, 0.02);  // apex within 2 % at 240 Hz
  // The two-finger hold threshold (the weight coming in quasi-statically) within 2 % of
  // 2 μs γ δ = m g (it comes out 0.5 % above at the defaults).
  EXPECT_LT(atDefaults("hold").error, 0.02);
  const sweep::Sample pile = atDefaults("pile");
  EXPECT_EQ(pile.error2, 0.0);  // no box centre went below the ground
  EXPECT_LT(pile.error, 5e-3);  // no corner deeper than 5 mm
}

TEST(Sweep, ResultsAreRepeatable) {
  const sweep::Sample a = atDefaults("push"), b = atDefaults("push");
  EXPECT_EQ(a.error, b.error);  // bit for bit: timings differ, errors never
}

TEST(Sweep, BadOptionsNameWhatIsWrong) {
  sweep::Options o;
  o.scenes = {"incline", "nosuch"};
  try {
    sweep::run({sweep::gripEngine()}, o);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "--scene: unknown scene 'nosuch' (one of incline, incline_stick, stack, bounce, "
                 "rotation, push, pile, hold)");
  }
  o.scenes = {};
  o.repeats = 0;
  try {
    sweep::validate(o);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "--repeats: must be positive (got 0)");
  }
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "grip_sweep_file";
  std::ofstream(file) << "x";
  EXPECT_THROW(sweep::write({}, (file / "sub").string()), Error);  // a file is in the way
}

}  // namespace
