// `grip view RECORDING [--port N]`: serves the viewer and the recording on 127.0.0.1 and prints
// the address to open. Ctrl-C stops it. A file that is not a complete grip recording is refused
// before anything is served (one line on stderr, exit 1).
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "web/http.hpp"
#include "web/report.hpp"

namespace grip::cli {

namespace {

volatile std::sig_atomic_t stopRequested = 0;
void onSignal(int) {
  stopRequested = 1;
}

int runView(std::string path, int port) {
  // A run's output directory stands for the recording in it.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec) &&
      std::filesystem::exists(std::filesystem::path(path) / "recording.jsonl", ec))
    path = (std::filesystem::path(path) / "recording.jsonl").string();
  web::checkRecording(path);
  web::Server server(port);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  const std::string name = std::filesystem::path(path).filename().string();
  std::printf("grip view: serving %s at http://127.0.0.1:%d/?url=recording.jsonl (Ctrl-C stops)\n",
              name.c_str(), server.port());
  std::fflush(stdout);
  server.serve(
      [&](const web::Request& r) -> web::Response {
        if (r.path == "/" || r.path == "/index.html")
          return {200, "text/html; charset=utf-8", std::string(web::viewerHtml()), ""};
        if (r.path == "/recording.jsonl")
          return {200, "application/jsonl; charset=utf-8", "", path};
        return {404, "text/plain; charset=utf-8", "not found: " + r.path + "\n", ""};
      },
      [] { return stopRequested != 0; });
  std::printf("grip view: stopped\n");
  return 0;
}

}  // namespace

Command addViewCommand(CLI::App& app) {
  auto* sub =
      app.add_subcommand("view", "open a recording in the web viewer (served on 127.0.0.1)");
  auto file = std::make_shared<std::string>();
  auto port = std::make_shared<int>(8000);
  sub->add_option("recording", *file,
                  "a recording.jsonl written by `grip run --out` (or that directory)")
      ->required();
  sub->add_option("--port", *port, "port on 127.0.0.1 (0: any free port)")
      ->check(CLI::Range(0, 65535));
  return {sub, [=] { return runView(*file, *port); }};
}

}  // namespace grip::cli
