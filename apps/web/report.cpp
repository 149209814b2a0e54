// The report page: the viewer with a thinned recording embedded, the checks and metrics, and an
// SVG still of the frame with the largest contact force.
#include "web/report.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/math.hpp"

namespace grip::web {

using nlohmann::json;

namespace {

constexpr int kMinVersion = 1, kMaxVersion = 2;  // recording versions this viewer reads

std::string escapeHtml(const std::string& s) {
  std::string r;
  for (char c : s) {
    switch (c) {
      case '&':
        r += "&amp;";
        break;
      case '<':
        r += "&lt;";
        break;
      case '>':
        r += "&gt;";
        break;
      case '"':
        r += "&quot;";
        break;
      default:
        r += c;
    }
  }
  return r;
}

// JSON text inside a <script> element: "</" may only appear inside JSON strings, where "<\/"
// reads back the same.
std::string scriptSafe(const std::string& s) {
  std::string r;
  r.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    r += s[i];
    if (s[i] == '<' && i + 1 < s.size() && s[i + 1] == '/') r += '\\';
  }
  return r;
}

// Rounds every floating-point number below `j` to `scale` (10^decimals) steps.
void roundNumbers(json& j, double scale) {
  if (j.is_number_float()) {
    j = std::round(j.get<double>() * scale) / scale;
  } else if (j.is_array() || j.is_object()) {
    for (auto& v : j) roundNumbers(v, scale);
  }
}

json parseLine(const std::string& line, const std::string& path, int lineNo) {
  json j = json::parse(line, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw Error(path, "line " + std::to_string(lineNo) + ": invalid JSON");
  return j;
}

void checkHeader(const json& h, const std::string& path) {
  if (!h.is_object() || h.value("format", "") != "grip-recording")
    throw Error(path, "not a grip recording (line 1 has no \"format\": \"grip-recording\")");
  const json v = h.value("version", json());
  if (!v.is_number_integer() || v.get<int>() < kMinVersion || v.get<int>() > kMaxVersion)
    throw Error(path, "unsupported recording version " + v.dump());
  if (!h.contains("bodies") || !h["bodies"].is_array() || !h.contains("hands") ||
      !h["hands"].is_array())
    throw Error(path, "the header has no bodies or hands");
}

// Total force of the pressing contacts of a frame (what makes a frame worth a still).
double contactForce(const json& frame) {
  double sum = 0.0;
  for (const json& c : frame.value("contacts", json::array())) {
    if (c.value("state", "") == "touch") continue;
    const json& f = c["force"];
    sum += std::hypot(f[0].get<double>(), f[1].get<double>(), f[2].get<double>());
  }
  return sum;
}

// ---- the SVG still ------------------------------------------------------------------------

// As the viewer's: clear of the contact states (green, orange, grey) and the arrows (red).
const char* const kBodyColors[] = {"#4e79a7", "#8e6bb8", "#3f9e9a", "#9c755f",
                                   "#5a6d8c", "#c267a3", "#6b8e23", "#7a5c99"};
const char* stateColor(const std::string& s) {
  return s == "stick" ? "#2ca02c" : s == "slip" ? "#ff7f0e" : "#9e9e9e";
}

Vec3 vec(const json& a, size_t at = 0) {
  return {a[at].get<double>(), a[at + 1].get<double>(), a[at + 2].get<double>()};
}
Transform pose(const json& a) {
  Transform t;
  t.p = vec(a);
  t.q = Quat(a[3].get<double>(), a[4].get<double>(), a[5].get<double>(), a[6].get<double>());
  t.q.normalize();
  return t;
}

// An orthographic camera from the front right, above (x right, y up on the page).
class Projector {
 public:
  Projector() {
    const double az = 35.0 * kPi / 180.0, el = 25.0 * kPi / 180.0;
    toViewer_ = Vec3(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    right_ = Vec3::UnitY().cross(toViewer_).normalized();
    up_ = toViewer_.cross(right_);
  }
  // Page coordinates in millimetres of the scene.
  std::array<double, 2> operator()(const Vec3& p) const {
    return {1000.0 * right_.dot(p), -1000.0 * up_.dot(p)};
  }
  double depth(const Vec3& p) const { return toViewer_.dot(p); }
  bool facing(const Vec3& n) const { return n.dot(toViewer_) > 1e-9; }

 private:
  Vec3 toViewer_, right_, up_;
};

struct Item {
  double depth = 0.0;
  std::string svg;
};

class Still {
 public:
  explicit Still(const Projector& pr) : pr_(pr) {}

  void polygon(const std::vector<Vec3>& pts, const Vec3& normal, const std::string& color,
               double opacity) {
    if (!pr_.facing(normal)) return;
    const Vec3 light = Vec3(0.3, 0.8, 0.5).normalized();
    const double shade = 0.6 + 0.4 * std::max(0.0, normal.dot(light));
    std::string s = "<polygon points=\"";
    double depth = 0.0;
    for (const Vec3& p : pts) {
      s += xy(p) + " ";
      depth += pr_.depth(p) / static_cast<double>(pts.size());
    }
    s += "\" fill=\"" + color + "\" fill-opacity=\"" + num(opacity) +
         "\" style=\"filter:brightness(" + num(shade) +
         ")\" stroke=\"#333\" stroke-opacity=\"0.35\" stroke-width=\"0.3\"/>";
    items_.push_back({depth, s});
  }

  void box(const Transform& t, const Vec3& h, const std::string& color, double opacity) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign : {-1, 1}) {
        Vec3 n = Vec3::Zero();
        n[axis] = sign;
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        std::vector<Vec3> pts;
        for (auto [sa, sb] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
          Vec3 c = Vec3::Zero();
          c[axis] = sign * h[axis];
          c[a] = sa * h[a];
          c[b] = sb * h[b];
          pts.push_back(t.apply(c));
        }
        polygon(pts, t.rotate(n), color, opacity);
      }
    }
  }

  void shape(const json& s, const Transform& t, const std::string& color, double opacity) {
    const std::string type = s.value("type", "");
    if (type == "box") {
      box(t, vec(s["halfExtents"]), color, opacity);
    } else if (type == "sphere") {
      const double r = 1000.0 * s["radius"].get<double>();
      items_.push_back({pr_.depth(t.p), "<circle " + cxy(t.p) + " r=\"" + num(r) + "\" fill=\"" +
                                            color + "\" fill-opacity=\"" + num(opacity) +
                                            "\" stroke=\"#333\" stroke-opacity=\"0.35\"/>"});
    } else if (type == "capsule") {
      const Vec3 axis = t.rotate(Vec3(0.0, s["halfHeight"].get<double>(), 0.0));
      const double w = 2000.0 * s["radius"].get<double>();
      items_.push_back({pr_.depth(t.p), "<line " + line(t.p - axis, t.p + axis) + " stroke=\"" +
                                            color + "\" stroke-opacity=\"" + num(opacity) +
                                            "\" stroke-width=\"" + num(w) +
                                            "\" stroke-linecap=\"round\"/>"});
    } else if (type == "hull" && s.contains("points") && s.contains("faces")) {
      std::vector<Vec3> local;
      for (const json& p : s["points"]) local.push_back(vec(p));
      for (const json& f : s["faces"]) {
        std::vector<Vec3> pts;
        for (const json& i : f) pts.push_back(t.apply(local.at(i.get<size_t>())));
        if (pts.size() < 3) continue;
        const Vec3 n = (pts[1] - pts[0]).cross(pts[2] - pts[0]);
        if (n.norm() > 0.0) polygon(pts, n.normalized(), color, opacity);
      }
    } else if (type == "compound") {
      for (const json& c : s["children"]) {
        Transform local;
        local.p = vec(c["position"]);
        const json& q = c["orientation"];
        local.q =
            Quat(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>());
        shape(c["shape"], t * local, color, opacity);
      }
    }
    if (type != "plane") extend(t.p, s);
  }

  // A square of the plane under the scene, always drawn first.
  void plane(const json& s, const Vec3& center, double size) {
    const Vec3 n = vec(s["normal"]).normalized();
    const Vec3 o = center - n * (n.dot(center) - s["offset"].get<double>());
    const Vec3 t1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    const Vec3 t2 = n.cross(t1);
    std::string svg = "<polygon points=\"";
    for (auto [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      svg += xy(o + size * (a * t1 + b * t2)) + " ";
    svg += "\" fill=\"#e4e8ec\" stroke=\"#b0b8c0\" stroke-width=\"0.5\"/>";
    items_.push_back({-1e300, svg});
  }

  void overlay(const std::string& svg) { overlay_ += svg; }
  void include(const Vec3& p) {
    const auto q = pr_(p);
    lo_ = {std::min(lo_[0], q[0]), std::min(lo_[1], q[1])};
    hi_ = {std::max(hi_[0], q[0]), std::max(hi_[1], q[1])};
  }

  std::string svg() {
    std::stable_sort(items_.begin(), items_.end(),
                     [](const Item& a, const Item& b) { return a.depth < b.depth; });
    if (!(lo_[0] <= hi_[0])) lo_ = {-100, -100}, hi_ = {100, 100};
    const double pad = 0.15 * std::max({hi_[0] - lo_[0], hi_[1] - lo_[1], 20.0});
    const double x = lo_[0] - pad, y = lo_[1] - pad;
    const double w = hi_[0] - lo_[0] + 2 * pad, h = hi_[1] - lo_[1] + 2 * pad;
    const double width = 640.0, height = std::round(width * h / w);
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width) +
                    "\" height=\"" + num(height) + "\" viewBox=\"" + num(x) + " " + num(y) + " " +
                    num(w) + " " + num(h) + "\">";
    s += "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"5\" "
         "markerHeight=\"5\" orient=\"auto-start-reverse\"><path d=\"M0 0L10 5L0 10z\" "
         "fill=\"#e02020\"/></marker></defs>";
    s += "<rect x=\"" + num(x) + "\" y=\"" + num(y) + "\" width=\"" + num(w) + "\" height=\"" +
         num(h) + "\" fill=\"#f4f6f9\"/>";
    for (const Item& i : items_) s += i.svg;
    s += overlay_ + "</svg>";
    return s;
  }

  std::string xy(const Vec3& p) const {
    const auto q = pr_(p);
    return num(q[0]) + "," + num(q[1]);
  }
  std::string cxy(const Vec3& p) const {
    const auto q = pr_(p);
    return "cx=\"" + num(q[0]) + "\" cy=\"" + num(q[1]) + "\"";
  }
  std::string line(const Vec3& a, const Vec3& b) const {
    const auto p = pr_(a), q = pr_(b);
    return "x1=\"" + num(p[0]) + "\" y1=\"" + num(p[1]) + "\" x2=\"" + num(q[0]) + "\" y2=\"" +
           num(q[1]) + "\"";
  }
  static std::string num(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", x);
    return b;
  }

 private:
  // The frame covers the body's origin and a margin of its size.
  void extend(const Vec3& p, const json& s) {
    double r = 0.02;
    if (s.contains("halfExtents")) r = vec(s["halfExtents"]).norm();
    if (s.contains("radius")) r = s["radius"].get<double>() + s.value("halfHeight", 0.0);
    for (int k = 0; k < 3; ++k) {
      Vec3 d = Vec3::Zero();
      d[k] = r;
      include(p + d), include(p - d);
    }
  }

  const Projector& pr_;
  std::vector<Item> items_;
  std::string overlay_;
  std::array<double, 2> lo_{1e300, 1e300}, hi_{-1e300, -1e300};
};

}  // namespace

std::string frameSvg(const json& header, const json& frame) {
  const Projector pr;
  Still still(pr);
  const json& bodies = header["bodies"];
  const json& poses = frame["bodies"];
  // The scene's centre and size: the non-plane bodies.
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (size_t i = 0; i < bodies.size() && i < poses.size(); ++i) {
    if (bodies[i]["shape"].value("type", "") == "plane") continue;
    const Vec3 p = vec(poses[i]);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  const bool any = lo.x() <= hi.x();
  const Vec3 center = any ? Vec3(0.5 * (lo + hi)) : Vec3::Zero();
  const double radius = any ? std::max(0.05, 0.5 * (hi - lo).norm()) : 0.5;
  for (size_t i = 0; i < bodies.size() && i < poses.size(); ++i) {
    const json& s = bodies[i]["shape"];
    if (s.value("type", "") == "plane") {
      still.plane(s, center, 3.0 * radius);
      continue;
    }
    const bool isStatic = bodies[i].value("type", "") == "static";
    still.shape(s, pose(poses[i]), isStatic ? "#c8ccd2" : kBodyColors[i % 8], 1.0);
  }
  // Hands: the tracked bones faint, the visual ones solid while the hand presses on something.
  const json& contacts = frame.value("contacts", json::array());
  const json& hands = header["hands"];
  for (size_t h = 0; h < hands.size() && h < frame["hands"].size(); ++h) {
    bool pressing = false;
    for (const json& c : contacts)
      pressing = pressing || (c["hand"] == h && c.value("state", "") != "touch");
    const json& fh = frame["hands"][h];
    for (size_t b = 0; b < hands[h]["bones"].size(); ++b) {
      const Transform tp = pose(fh["bones"][b]);
      if ((tp.p - center).norm() > radius + 1.0) continue;  // parked far away
      const json& s = hands[h]["bones"][b]["shape"];
      still.shape(s, tp, "#e0ac8a", 0.3);
      if (pressing) still.shape(s, pose(fh["visual"][b]), "#e0ac8a", 1.0);
    }
  }
  double maxForce = 0.0;
  for (const json& c : contacts) maxForce = std::max(maxForce, vec(c["force"]).norm());
  for (const json& c : contacts) {
    const Vec3 p = vec(c["point"]), f = vec(c["force"]);
    // The force on the body, its tip at the contact point; the largest is 60 % of the scene radius.
    if (maxForce > 0.0 && f.norm() > 1e-3 * maxForce) {
      const Vec3 tail = p - f * (0.6 * radius / maxForce);
      still.overlay("<line " + still.line(tail, p) +
                    " stroke=\"#e02020\" stroke-width=\"1.2\" marker-end=\"url(#arrow)\"/>");
      still.include(tail);
    }
    still.overlay("<circle " + still.cxy(p) + " r=\"" + Still::num(1.5 + radius * 20.0) +
                  "\" fill=\"" + stateColor(c.value("state", "")) + "\" stroke=\"#fff\"/>");
  }
  return still.svg();
}

json checkRecording(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path, "is a directory");
  std::string first;
  if (!std::getline(in, first) || first.empty()) throw Error(path, "the recording is empty");
  const json header = json::parse(first, nullptr, false);
  if (header.is_discarded()) throw Error(path, "not a grip recording (line 1 is not JSON)");
  checkHeader(header, path);
  // The last line: a complete recording ends with {"end": true, ...}.
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff tail = std::min<std::streamoff>(size, 4096);
  std::string buf(static_cast<size_t>(tail), '\0');
  in.seekg(size - tail);
  in.read(buf.data(), tail);
  while (!buf.empty() && (buf.back() == '\n' || buf.back() == '\r')) buf.pop_back();
  const size_t nl = buf.rfind('\n');
  const json last = json::parse(nl == std::string::npos ? buf : buf.substr(nl + 1), nullptr, false);
  if (last.is_discarded() || !last.is_object() || last.value("end", false) != true)
    throw Error(path, "truncated recording (no end line)");
  return header;
}

std::string reportHtml(const std::string& path, const json& metrics, const ReportOptions& options,
                       ReportStats* statsOut) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
  std::string line;
  if (!std::getline(in, line)) throw Error(path, "the recording is empty");
  json header = parseLine(line, path, 1);
  checkHeader(header, path);
  const double frameDt = header.value("dt", 0.0) * header.value("recordEvery", 1);
  ReportStats st;
  if (frameDt > 0.0)
    st.keepEvery =
        std::max(1, static_cast<int>(std::ceil(1.0 / (frameDt * options.maxFps) - 1e-9)));
  const double scale = std::pow(10.0, options.decimals);

  std::string frames, lastLine;
  bool lastKept = true, ended = false;
  json best;
  double bestForce = -1.0;
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty()) continue;
    json j = parseLine(line, path, lineNo);
    if (j.value("end", false) == true) {
      ended = true;
      break;
    }
    const double force = contactForce(j);
    if (force > bestForce) bestForce = force, best = j;
    for (const char* k : {"bodies", "hands", "contacts"})
      if (j.contains(k)) roundNumbers(j[k], scale);
    lastLine = j.dump();
    lastKept = st.framesIn % st.keepEvery == 0;
    if (lastKept) frames += lastLine + "\n", ++st.framesKept;
    ++st.framesIn;
  }
  if (!ended) throw Error(path, "truncated recording (no end line)");
  if (st.framesIn == 0) throw Error(path, "the recording has no frames");
  if (!lastKept) frames += lastLine + "\n", ++st.framesKept;  // always end on the final state
  st.keyFrame = best.value("frame", 0);

  header["recordEvery"] = header.value("recordEvery", 1) * st.keepEvery;
  header["report"] = {{"sourceFrames", st.framesIn},
                      {"keepEvery", st.keepEvery},
                      {"maxFps", options.maxFps},
                      {"decimals", options.decimals}};
  const std::string recording =
      header.dump() + "\n" + frames +
      json(
          {{"end", true}, {"frames", st.framesKept}, {"stateHash", metrics.value("stateHash", "")}})
          .dump() +
      "\n";

  // The static part: readable without the script.
  const std::string scene = metrics.value("scene", header.value("scene", "scene"));
  std::string r = "<section id=\"report\"><h1>" + escapeHtml(scene) + ": report</h1>";
  r += "<h2>Checks</h2>";
  const json checks = metrics.value("checks", json::array());
  if (checks.empty()) {
    r += "<p>This scene has no checks.</p>";
  } else {
    r += "<table id=\"checks\"><tr><th>result</th><th>check</th><th>measured</th></tr>";
    for (const json& c : checks) {
      const bool ok = c.value("passed", false);
      r += std::string("<tr><td class=\"") + (ok ? "pass\">PASS" : "fail\">FAIL") + "</td><td>" +
           escapeHtml(c.value("label", "")) + "</td><td>" + escapeHtml(c.value("detail", "")) +
           "</td></tr>";
    }
    r += "</table>";
  }
  char caption[160];
  std::snprintf(caption, sizeof caption,
                "Frame %d (t = %.3f s), the frame with the largest total contact force (%.3g N).",
                st.keyFrame, best.value("t", 0.0), std::max(0.0, bestForce));
  r += "<h2>Key frame</h2><figure id=\"still\">" + frameSvg(header, best) + "<figcaption>" +
       caption +
       " Red: contact forces on the body; green/orange dots: sticking/slipping "
       "contacts.</figcaption></figure>";
  r += "<h2>Metrics</h2><table id=\"metrics\">";
  auto row = [&](const std::string& k, const std::string& v) {
    r += "<tr><th>" + escapeHtml(k) + "</th><td>" + escapeHtml(v) + "</td></tr>";
  };
  auto text = [](const json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (!v.is_number_float()) return v.dump();
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v.get<double>());
    return std::string(b);
  };
  for (const char* k : {"method", "seed", "dt", "steps", "simulatedTime", "wallTime",
                        "realtimeFactor", "stateHash"})
    if (metrics.contains(k)) row(k, text(metrics[k]));
  for (const char* group : {"hands", "energy"})
    if (metrics.contains(group) && metrics[group].is_object())
      for (const auto& [k, v] : metrics[group].items()) row(std::string(group) + "." + k, text(v));
  r += "</table>";
  char note[320];
  std::snprintf(note, sizeof note,
                "The viewer above plays %d of the recording's %d frames (every %d-th and the "
                "last: at most %g frames per simulated second), poses and forces rounded to %d "
                "decimals. The full recording is recording.jsonl; open it with grip view.",
                st.framesKept, st.framesIn, st.keepEvery, options.maxFps, options.decimals);
  r += "<p class=\"note\">" + std::string(note) + "</p></section>\n";
  r += "<script type=\"application/x-grip-recording\" id=\"grip-recording\">\n" +
       scriptSafe(recording) + "</script>\n";

  std::string page(viewerHtml());
  const std::string marker = "<!--GRIP-REPORT-->";
  const size_t at = page.find(marker);
  if (at == std::string::npos) throw Error("viewer", "the embedded page has no report marker");
  page.replace(at, marker.size(), r);
  st.bytes = page.size();
  if (statsOut) *statsOut = st;
  return page;
}

ReportStats writeReport(const std::string& recordingPath, const json& metrics,
                        const std::string& outPath, const ReportOptions& options) {
  ReportStats st;
  const std::string page = reportHtml(recordingPath, metrics, options, &st);
  const std::string tmp = outPath + ".partial";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error(outPath, std::string("cannot write: ") + std::strerror(errno));
  const bool ok = std::fwrite(page.data(), 1, page.size(), f) == page.size();
  const bool closed = std::fclose(f) == 0;
  std::error_code ec;
  if (!ok || !closed) {
    std::filesystem::remove(tmp, ec);
    throw Error(outPath, "write failed");
  }
  std::filesystem::rename(tmp, outPath, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw Error(outPath, "cannot rename: " + ec.message());
  }
  return st;
}

}  // namespace grip::web
