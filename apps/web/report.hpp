// The viewer page embedded in the binary, and the self-contained report of a run: the viewer
// with the recording inside it, the checks and metrics, and an SVG still of a key frame.
// See docs/viewer.md.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace grip::web {

// The viewer: one HTML file with its script and styles (built from web/ by esbuild, generated
// into the build as a source file).
std::string_view viewerHtml();

// Reads the header (line 1) and the end line of a recording file. Throws grip::Error naming
// the file when it cannot be read, is not a grip recording of a known version, or has no end
// line (truncated). Returns the header.
nlohmann::json checkRecording(const std::string& path);

struct ReportOptions {
  double maxFps = 60.0;  // embedded frames per simulated second, at most
  int decimals = 6;      // poses and forces rounded to this many decimals (1 um, 1 uN)
};

struct ReportStats {
  int framesIn = 0;    // frames in the recording
  int framesKept = 0;  // frames embedded
  int keepEvery = 1;   // every n-th frame kept (and always the last)
  int keyFrame = 0;    // the frame number shown as the still
  size_t bytes = 0;    // the size of the page
};

// The report page of a recording file and its metrics (metrics.json's content).
std::string reportHtml(const std::string& recordingPath, const nlohmann::json& metrics,
                       const ReportOptions& options = {}, ReportStats* stats = nullptr);
// Writes reportHtml(...) to `outPath` (via a .partial file and a rename).
ReportStats writeReport(const std::string& recordingPath, const nlohmann::json& metrics,
                        const std::string& outPath, const ReportOptions& options = {});

// An SVG still of one frame (a frame line of the recording) under its header: bodies, the hands
// near the scene, contact points coloured by state and the contact forces as red arrows.
std::string frameSvg(const nlohmann::json& header, const nlohmann::json& frame);

}  // namespace grip::web
