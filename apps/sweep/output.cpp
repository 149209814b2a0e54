// The sweep's files: sweep.csv and a self-written SVG chart (no plotting dependency).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "sweep/sweep.hpp"

namespace grip::sweep {

namespace {

std::string format(const char* fmt, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, x);
  return buf;
}

// A chart needs positive values: an error of exactly 0 (a stick that never moved, a pile
// with no penetration) is drawn at the floor of the panel and said so in its title.
constexpr double kFloor = 1e-9;

const char* colour(size_t engine) {
  static const char* c[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};
  return c[engine % 5];
}

struct Axis {
  double lo, hi;  // log10 range, whole decades
  double px0, px1;
  double map(double v) const { return px0 + (std::log10(v) - lo) / (hi - lo) * (px1 - px0); }
};

Axis axisFor(const std::vector<double>& v, double px0, double px1) {
  double lo = 1e300, hi = -1e300;
  for (double x : v) lo = std::min(lo, std::log10(x)), hi = std::max(hi, std::log10(x));
  lo = std::floor(lo), hi = std::ceil(hi);
  if (hi <= lo) hi = lo + 1;
  return {lo, hi, px0, px1};
}

// Samples of one engine on one scene that no other sample beats in both time and error,
// ordered by time.
std::vector<const Sample*> paretoFront(std::vector<const Sample*> s) {
  std::sort(s.begin(), s.end(), [](const Sample* a, const Sample* b) {
    return a->seconds != b->seconds ? a->seconds < b->seconds : a->error < b->error;
  });
  std::vector<const Sample*> front;
  for (const Sample* x : s)
    if (front.empty() || std::max(x->error, kFloor) < std::max(front.back()->error, kFloor))
      front.push_back(x);
  return front;
}

}  // namespace

std::string csv(const std::vector<Sample>& samples) {
  std::string out =
      "engine,scene,dt,substeps,iterations,seconds,error,error_name,error2,error2_name,default\n";
  for (const Sample& s : samples) {
    out += s.engine + "," + s.scene + "," + format("%.9g", s.settings.dt) + "," +
           std::to_string(s.settings.substeps) + "," + std::to_string(s.settings.iterations) + "," +
           format("%.6g", s.seconds) + "," + format("%.6g", s.error) + "," + s.errorName + "," +
           (std::isnan(s.error2) ? "" : format("%.6g", s.error2)) + "," + s.error2Name + "," +
           (s.isDefault ? "1" : "0") + "\n";
  }
  return out;
}

std::string svg(const std::vector<Sample>& input) {
  // A scene's second metric gets a panel of its own when it is an error too (the rotation's
  // energy), not when it is context (a stack's settling, the pile's count below ground).
  std::vector<Sample> samples = input;
  std::vector<std::string> scenes, engines;
  auto once = [](std::vector<std::string>& v, const std::string& x) {
    if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
  };
  for (const Sample& s : input) {
    once(scenes, s.scene);
    once(engines, s.engine);
    if (s.error2Name.ends_with("_error")) {
      Sample t = s;
      t.scene = s.scene + "_" + s.error2Name.substr(0, s.error2Name.find('_'));
      t.error = s.error2;
      t.errorName = s.error2Name;
      samples.push_back(t);
      once(scenes, t.scene);  // beside its scene
    }
  }
  constexpr int kW = 380, kH = 290, kCols = 3, kTop = 40;
  const int cols = std::min<int>(kCols, std::max<int>(1, static_cast<int>(scenes.size())));
  const int rows = (static_cast<int>(scenes.size()) + cols - 1) / cols;
  const int width = cols * kW, height = kTop + rows * kH;
  std::string o = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) +
                  "\" height=\"" + std::to_string(height) + "\" viewBox=\"0 0 " +
                  std::to_string(width) + " " + std::to_string(height) +
                  "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  // Legend: one colour per engine; the ring marks each engine's default setting.
  double lx = 10;
  for (size_t e = 0; e < engines.size(); ++e) {
    o += "<circle cx=\"" + format("%.0f", lx + 5) + "\" cy=\"16\" r=\"4\" fill=\"" + colour(e) +
         "\"/><text x=\"" + format("%.0f", lx + 13) + "\" y=\"20\">" + engines[e] + "</text>\n";
    lx += 20 + 8 * engines[e].size();
  }
  o += "<text x=\"" + format("%.0f", lx + 10) +
       "\" y=\"20\">line: Pareto front; ring: default setting; x: wall s per simulated s "
       "(fastest of the repeats); y: error</text>\n";
  for (size_t k = 0; k < scenes.size(); ++k) {
    const int ox = static_cast<int>(k % cols) * kW, oy = kTop + static_cast<int>(k / cols) * kH;
    std::vector<const Sample*> mine;
    std::vector<double> xs, ys;
    bool floored = false;
    for (const Sample& s : samples)
      if (s.scene == scenes[k]) {
        mine.push_back(&s);
        xs.push_back(std::max(s.seconds, 1e-12));
        ys.push_back(std::max(s.error, kFloor));
        floored |= s.error < kFloor;
      }
    const Axis ax = axisFor(xs, ox + 55.0, ox + kW - 15.0);
    const Axis ay = axisFor(ys, oy + kH - 40.0, oy + 25.0);
    o += "<g class=\"panel\" id=\"panel-" + scenes[k] + "\">\n";
    o += "<text x=\"" + std::to_string(ox + 55) + "\" y=\"" + std::to_string(oy + 15) +
         "\" font-weight=\"bold\">" + scenes[k] + ": " + mine.front()->errorName +
         (floored ? " (below 1e-9: drawn at 1e-9)" : "") + "</text>\n";
    o += "<rect x=\"" + format("%.1f", ax.px0) + "\" y=\"" + format("%.1f", ay.px1) +
         "\" width=\"" + format("%.1f", ax.px1 - ax.px0) + "\" height=\"" +
         format("%.1f", ay.px0 - ay.px1) + "\" fill=\"none\" stroke=\"#888\"/>\n";
    for (double d = ax.lo; d <= ax.hi; ++d) {
      const double x = ax.map(std::pow(10.0, d));
      o += "<line x1=\"" + format("%.1f", x) + "\" y1=\"" + format("%.1f", ay.px1) + "\" x2=\"" +
           format("%.1f", x) + "\" y2=\"" + format("%.1f", ay.px0) +
           "\" stroke=\"#eee\"/><text x=\"" + format("%.1f", x - 12) + "\" y=\"" +
           format("%.1f", ay.px0 + 14) + "\">1e" + format("%.0f", d) + "</text>\n";
    }
    for (double d = ay.lo; d <= ay.hi; ++d) {
      const double y = ay.map(std::pow(10.0, d));
      o += "<line x1=\"" + format("%.1f", ax.px0) + "\" y1=\"" + format("%.1f", y) + "\" x2=\"" +
           format("%.1f", ax.px1) + "\" y2=\"" + format("%.1f", y) +
           "\" stroke=\"#eee\"/><text x=\"" + format("%.1f", ax.px0 - 38) + "\" y=\"" +
           format("%.1f", y + 4) + "\">1e" + format("%.0f", d) + "</text>\n";
    }
    for (size_t e = 0; e < engines.size(); ++e) {
      std::vector<const Sample*> theirs;
      for (const Sample* s : mine)
        if (s->engine == engines[e]) theirs.push_back(s);
      if (theirs.empty()) continue;
      auto px = [&](const Sample* s) {
        return format("%.1f", ax.map(std::max(s->seconds, 1e-12))) + "," +
               format("%.1f", ay.map(std::max(s->error, kFloor)));
      };
      std::string points;
      for (const Sample* s : paretoFront(theirs)) points += px(s) + " ";
      o += "<polyline fill=\"none\" stroke=\"" + std::string(colour(e)) +
           "\" stroke-width=\"1.5\" points=\"" + points + "\"/>\n";
      for (const Sample* s : theirs) {
        const std::string c = px(s);
        const std::string cx = c.substr(0, c.find(',')), cy = c.substr(c.find(',') + 1);
        o += "<circle cx=\"" + cx + "\" cy=\"" + cy + "\" r=\"2.5\" fill=\"" + colour(e) +
             "\" fill-opacity=\"0.6\"><title>" + s->engine +
             " dt=" + format("%.6g", s->settings.dt) +
             " substeps=" + std::to_string(s->settings.substeps) +
             " iterations=" + std::to_string(s->settings.iterations) + "</title></circle>\n";
        if (s->isDefault)
          o += "<circle cx=\"" + cx + "\" cy=\"" + cy + "\" r=\"6\" fill=\"none\" stroke=\"" +
               colour(e) + "\" stroke-width=\"2\"/>\n";
      }
    }
    o += "</g>\n";
  }
  o += "</svg>\n";
  return o;
}

void makeOutputDir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw Error("--out", "cannot create the output directory " + dir);
}

void write(const std::vector<Sample>& samples, const std::string& dir) {
  makeOutputDir(dir);
  for (const auto& [name, text] : {std::pair{std::string("sweep.csv"), csv(samples)},
                                   std::pair{std::string("sweep.svg"), svg(samples)}}) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    std::ofstream f(path, std::ios::binary);
    f << text;
    if (!f.good()) throw Error("--out", "cannot write " + path);
  }
}

}  // namespace grip::sweep
