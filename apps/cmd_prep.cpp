// `grip prep`: turns a mesh (OFF, OBJ, STL, PLY) or a built-in object into a runtime asset.
// Built only with the offline library (GRIP_BUILD_VOXEL=ON, which defines GRIP_HAVE_VOXEL).
#ifdef GRIP_HAVE_VOXEL
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "core/error.hpp"
#include "voxel/voxel.hpp"

namespace grip::cli {

namespace {

struct PrepArgs {
  std::string mesh;
  std::string builtin;
  std::string output;
  std::string lod = "high";
  double voxel = 0.0;
  double density = 1000.0;
  int sdfResolution = 48;
  std::string exportBoxes, exportSdf, exportMesh;
  bool noFillHoles = false;
  bool allowSelfIntersections = false;
  bool progress = false;
  bool quiet = false;
};

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

std::string fmt(const char* f, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, a);
  return buf;
}

int runPrep(const PrepArgs& args) {
  using namespace grip::voxel;
  if (args.mesh.empty() == args.builtin.empty())
    throw Error("prep", "give either a MESH file or --builtin NAME");
  std::vector<Lod> lods;
  if (args.lod == "all") {
    lods = {Lod::Low, Lod::Medium, Lod::High, Lod::VeryHigh};
    if (args.output.find("{lod}") == std::string::npos)
      throw Error("--output", "with --lod all the output name must contain {lod}");
  } else {
    lods = {parseLod(args.lod)};
  }
  const auto t0 = std::chrono::steady_clock::now();
  RepairOptions ro;
  ro.fillHoles = !args.noFillHoles;
  ro.allowSelfIntersections = args.allowSelfIntersections;
  MeshReport report;
  const std::string source = args.mesh.empty() ? "builtin:" + args.builtin : args.mesh;
  Mesh mesh = args.mesh.empty() ? repairMesh(builtinMesh(args.builtin), ro, &report)
                                : loadMesh(args.mesh, ro, &report);
  const double loadSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!args.exportMesh.empty()) writeMesh(args.exportMesh, mesh);
  if (!args.quiet) {
    std::cout << source << ": " << report.inputVertices << " vertices, " << report.inputFaces
              << " faces -> " << mesh.triangles.size() << " triangles ("
              << fmt("%.2f s", loadSeconds) << ")\n";
    for (const auto& r : report.repairs) std::cout << "  repaired: " << r << "\n";
    for (const auto& w : report.warnings) std::cout << "  warning: " << w << "\n";
  }
  // Progress lines for long meshes (or on request), on stderr so the summary stays clean.
  const bool showProgress = args.progress || mesh.triangles.size() > 200000;
  for (Lod lod : lods) {
    PrepOptions po;
    po.lod = lod;
    po.voxelSize = args.voxel;
    po.density = args.density;
    po.sdfMaxResolution = args.sdfResolution;
    po.vdbPath = replaceAll(args.exportSdf, "{lod}", lodName(lod));
    if (showProgress) {
      po.progress = [](const std::string& stage, double f) {
        std::cerr << "  [" << stage << "] " << static_cast<int>(100.0 * f) << "%\n";
      };
    }
    PrepStats st;
    const AssetData asset = prepare(mesh, po, &st);
    const std::vector<uint8_t> bytes = encodeAsset(asset);
    decodeAsset(bytes);  // never write what the runtime would refuse
    const std::string out = replaceAll(args.output, "{lod}", lodName(lod));
    writeAssetFile(out, asset);
    if (!args.exportBoxes.empty())
      exportBoxesObj(replaceAll(args.exportBoxes, "{lod}", lodName(lod)), asset);
    if (!args.quiet) {
      std::cout << "  " << (args.voxel > 0.0 ? std::string("custom") : lodName(lod)) << ": voxel "
                << fmt("%.4g m", asset.voxelSize) << ", lattice " << st.gridSize[0] << "x"
                << st.gridSize[1] << "x" << st.gridSize[2] << ", " << st.voxels
                << " interior voxels -> " << st.boxes << " boxes; volume "
                << fmt("%.6g m^3", st.exactVolume) << " exact, error "
                << fmt("%+.2f %%", 100.0 * st.volumeError()) << "; mass "
                << fmt("%.4g kg", asset.mass.mass) << "; sdf " << st.sdfBricks << " bricks at "
                << fmt("%.4g m", st.sdfSpacing) << "; " << out << " "
                << fmt("%.1f KB", bytes.size() / 1024.0) << ", " << fmt("%.2f s", st.seconds)
                << "\n";
    }
  }
  return 0;
}

}  // namespace

Command addPrepCommand(CLI::App& app) {
  auto args = std::make_shared<PrepArgs>();
  CLI::App* sub = app.add_subcommand(
      "prep", "Prepare a concave object: mesh -> voxel boxes + signed-distance field asset");
  sub->add_option("mesh", args->mesh, "input mesh (.off, .obj, .stl, .ply)");
  sub->add_option("--builtin", args->builtin,
                  "use a built-in object instead: mug, axe, torus, l-block, figurine");
  sub->add_option("-o,--output", args->output, "output asset (.grip); {lod} is replaced")
      ->required();
  auto* lod =
      sub->add_option("--lod", args->lod, "level of detail: low, medium, high, very-high, or all");
  auto* voxel = sub->add_option("--voxel", args->voxel, "voxel size in metres (overrides --lod)");
  lod->excludes(voxel);
  sub->add_option("--density", args->density, "density in kg/m^3 (default 1000)");
  sub->add_option("--sdf-resolution", args->sdfResolution,
                  "SDF samples across the longest side at most (default 48; 0: voxel size)");
  sub->add_option("--export-boxes", args->exportBoxes, "also write the boxes as .obj");
  sub->add_option("--export-sdf", args->exportSdf, "also write the SDF as an OpenVDB .vdb");
  sub->add_option("--export-mesh", args->exportMesh, "also write the repaired mesh (.off/.obj)");
  sub->add_flag("--no-fill-holes", args->noFillHoles, "refuse open meshes instead of closing them");
  sub->add_flag("--allow-self-intersections", args->allowSelfIntersections,
                "prepare self-intersecting meshes anyway (mass properties double-count overlaps)");
  sub->add_flag("--progress", args->progress, "print progress of each stage on stderr");
  sub->add_flag("-q,--quiet", args->quiet, "print nothing on success");
  return {sub, [args] { return runPrep(*args); }};
}

}  // namespace grip::cli

#endif  // GRIP_HAVE_VOXEL
