// Bad input: every broken mesh is refused with a message naming the problem, or repaired in a
// documented way; never a crash, never a silently wrong asset.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "voxel_test_util.hpp"

namespace grip::voxel::test {
namespace {

namespace fs = std::filesystem;

std::string writeFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "grip_voxel_input_test";
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The message loadMesh (and, if it loads, preparation at `lod`) fails with; "" on success.
std::string failure(const std::string& path, Lod lod = Lod::Low, RepairOptions ro = {}) {
  try {
    PrepOptions opt;
    opt.lod = lod;
    prepare(loadMesh(path, ro), opt);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kTetra = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

TEST(MeshInput, AGoodTetrahedronLoads) {
  EXPECT_EQ(failure(writeFile("tet.off", std::string("OFF\n4 4 0\n") + kTetra)), "");
}

TEST(MeshInput, FileProblemsAreNamed) {
  const auto has = [](const std::string& msg, const char* what) {
    return msg.find(what) != std::string::npos;
  };
  EXPECT_TRUE(has(failure(writeFile("a.xyz", "hello")), "unknown mesh format '.xyz'"));
  EXPECT_TRUE(has(failure(writeFile("noext", "hello")), "unknown mesh format"));
  EXPECT_TRUE(has(failure("/nonexistent/dir/x.off"), "no such file"));
  EXPECT_TRUE(has(failure(writeFile("empty.off", "")), "empty file"));
  EXPECT_TRUE(has(failure(writeFile("zero.off", "OFF\n0 0 0\n")), "empty mesh"));
  EXPECT_TRUE(has(failure(writeFile("trunc.off", "OFF\n8 12 0\n0 0 0\n1 0 0\n")), "truncated"));
  EXPECT_TRUE(has(failure(writeFile("trunc2.off", std::string("OFF\n4 4 0\n") +
                                                      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0")),
                  "cannot parse as off"));
  EXPECT_TRUE(
      has(failure(writeFile("liar.off", "OFF\n100000000 100000000 0\n0 0 0\n")), "absurd size"));
  EXPECT_TRUE(has(failure(writeFile("nan.off",
                                    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 nan\n"
                                    "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n")),
                  "non-finite number on line 6"));
  EXPECT_TRUE(has(failure(writeFile("inf.obj",
                                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e999\n"
                                    "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")),
                  "non-finite"));
  EXPECT_TRUE(has(failure(writeFile("huge.off",
                                    "OFF\n4 4 0\n0 0 0\n1e6 0 0\n0 1e6 0\n0 0 1e6\n"
                                    "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n")),
                  "absurd size"));
  EXPECT_TRUE(has(failure(writeFile("trunc.stl", "solid x\nfacet normal 0 0 1\nouter loop\n")),
                  "truncated"));
  EXPECT_TRUE(has(failure(writeFile("bin.stl", std::string(84, 'x') + std::string(30, '\0'))),
                  "binary STL"));
  EXPECT_TRUE(has(failure(writeFile("bad.ply", "ply\nformat nonsense\n")), "cannot parse as ply"));
}

TEST(MeshInput, GeometryProblemsAreNamedOrRepaired) {
  // Non-manifold: a fin on one edge of a tetrahedron (three faces on edge 0-1).
  EXPECT_NE(failure(writeFile("fin.off", std::string("OFF\n5 5 0\n") +
                                             "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 -1 0\n"
                                             "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n3 0 4 1\n"))
                .find("non-manifold: 1 edge shared by more than two faces"),
            std::string::npos);
  // Two tetrahedra that pass through each other.
  EXPECT_NE(
      failure(writeFile("cross.off", std::string("OFF\n8 8 0\n") +
                                         "0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.2 0.2 0.2\n1.2 0.2 0.2\n"
                                         "0.2 1.2 0.2\n0.2 0.2 1.2\n"
                                         "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
                                         "3 4 6 5\n3 4 5 7\n3 5 6 7\n3 4 7 6\n"))
          .find("self-intersecting"),
      std::string::npos);
  // A flat sheet: closing it encloses nothing.
  EXPECT_NE(failure(writeFile("sheet.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
                .find("cannot be closed into a solid"),
            std::string::npos);
  // An open tetrahedron (one face missing): repaired by default, refused on request.
  const std::string open =
      writeFile("open.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
  MeshReport report;
  const Mesh m = loadMesh(open, {}, &report);
  ASSERT_EQ(report.repairs.size(), 1u);
  EXPECT_EQ(report.repairs[0], "filled 1 hole (3 boundary edges) with 1 triangle");
  EXPECT_NEAR(meshMass(m.vertices, m.triangles, 1.0).volume, 1.0 / 6.0, 1e-12);
  RepairOptions strict;
  strict.fillHoles = false;
  EXPECT_NE(failure(open, Lod::Low, strict).find("open: 1 hole (3 boundary edges)"),
            std::string::npos);
  // Inside-out and duplicated vertices: repaired and reported.
  Mesh inverted;
  inverted.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
  inverted.triangles = {{0, 1, 2}, {0, 3, 4}, {1, 3, 2}, {0, 2, 3}};
  MeshReport r2;
  const Mesh fixed = repairMesh(inverted, {}, &r2);
  EXPECT_NEAR(meshMass(fixed.vertices, fixed.triangles, 1.0).volume, 1.0 / 6.0, 1e-12);
  ASSERT_EQ(r2.repairs.size(), 2u);
  EXPECT_EQ(r2.repairs[0], "merged or dropped 1 duplicate or unused vertex");
  EXPECT_EQ(r2.repairs[1], "oriented the faces outward");
  // Thinner than a voxel at the chosen level of detail.
  EXPECT_NE(failure(writeFile("thin.off", std::string("OFF\n8 12 0\n") +
                                              "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 0.001\n1 0 0.001\n"
                                              "0 1 0.001\n1 1 0.001\n"
                                              "3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n"
                                              "3 0 5 4\n3 2 6 7\n3 2 7 3\n3 0 4 6\n3 0 6 2\n"
                                              "3 1 3 7\n3 1 7 5\n"))
                .find("too coarse"),
            std::string::npos);
}

struct Broken {
  const char* file;
  const char* message;  // expected part of the one-line error
};

TEST(MeshInput, CgalDataBrokenMeshesGiveTheirMessages) {
  if (!haveCgalData()) GTEST_SKIP() << "libcgal-demo not installed";
  const Broken cases[] = {
      {"triangle.off", "open: 1 hole (3 boundary edges) that cannot be closed into a solid"},
      {"quad.off", "open: 1 hole (4 boundary edges) that cannot be closed into a solid"},
      {"diplodocus.off", "non-manifold: 2 edges shared by more than two faces"},
      {"elephant-with-holes.off", "self-intersecting"},
      {"tetra_intersected_by_triangle.off", "self-intersecting"},
      {"bull.off", "self-intersecting: 3 pairs of faces intersect"},
      {"pig.stl", "self-intersecting"},
      {"mesh_with_colors.off", "could not all be closed"},
      {"b9.ply", "no faces"},
      {"blade.off", "too coarse"},
  };
  for (const Broken& c : cases) {
    const std::string path = cgalMesh(c.file);
    ASSERT_FALSE(path.empty()) << c.file;
    const std::string msg = failure(path);
    EXPECT_NE(msg.find(c.message), std::string::npos) << c.file << ": got \"" << msg << "\"";
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line";
  }
  // Documented repairs: an open cube is closed, a shuffled one reoriented.
  for (const char* file : {"open_cube.off", "cube-ouvert.off", "cube-shuffled.off"}) {
    MeshReport report;
    const Mesh m = loadMesh(cgalMesh(file), {}, &report);
    EXPECT_FALSE(report.repairs.empty()) << file;
    EXPECT_GT(meshMass(m.vertices, m.triangles, 1.0).volume, 0.0) << file;
  }
}

// Inputs found by the fuzzer (fuzz/fuzz_mesh.cpp), kept in tests/voxel/data/ and in the fuzz
// corpus: each once crashed or hit undefined behaviour inside CGAL's readers.
TEST(MeshInput, FuzzerFindingsAreRefusedWithAMessage) {
  // CGAL's OFF reader converts a face index read as a double to size_t (2e33: undefined).
  const std::string off = sourceDir() + "/tests/voxel/data/regression_off_huge_index.off";
  EXPECT_NE(failure(off).find("absurd number '2e33' on line 8"), std::string::npos) << failure(off);
  // ...and allocates a face's vertex count before reading it (350 million here: 2.8 GB).
  const std::string count = sourceDir() + "/tests/voxel/data/regression_off_huge_face_count.off";
  EXPECT_NE(failure(count).find("truncated: the face on line 48 claims 350542535 vertices"),
            std::string::npos)
      << failure(count);
  // CGAL's PLY reader adds a property to the last element without checking there is one.
  const std::string ply =
      sourceDir() + "/tests/voxel/data/regression_ply_property_before_element.ply";
  EXPECT_NE(failure(ply).find("malformed PLY header: a property before any element on line 4"),
            std::string::npos)
      << failure(ply);
  const std::string uchar = sourceDir() + "/tests/voxel/data/regression_ply_uchar_coordinate.ply";
  EXPECT_NE(failure(uchar).find("vertex coordinate z has type 'uchar' (expected float or double) "
                                "on line 6"),
            std::string::npos)
      << failure(uchar);
  // A vertex count of 4.7e32 in the header used to be converted to an integer for the message.
  const std::string nv = sourceDir() + "/tests/voxel/data/regression_off_huge_vertex_count.off";
  EXPECT_NE(failure(nv).find("truncated: the header claims 4666666666666666"), std::string::npos)
      << failure(nv);
  // "12-19" in a face line: a stream reader takes -19 from it (a negative size_t index).
  const std::string glued =
      sourceDir() + "/tests/voxel/data/regression_off_glued_negative_index.off";
  EXPECT_NE(failure(glued).find("negative number '-19' in the face on line 51"), std::string::npos)
      << failure(glued);
  // A cube with a displaced vertex (non-planar quads) and a face line glued to the next: CGAL
  // 5.5's triangulate_faces wrote to freed memory on it. Quads are now fanned in the soup.
  const std::string quads = sourceDir() + "/tests/voxel/data/regression_obj_nonplanar_quad_fan.obj";
  EXPECT_NE(failure(quads).find("non-manifold: the faces do not join into a surface"),
            std::string::npos)
      << failure(quads);
  // Binary OFF whose two counts add up beyond an int: CGAL converted 2.8e9 to int (undefined).
  const std::string binary =
      sourceDir() + "/tests/voxel/data/regression_off_binary_huge_counts.off";
  EXPECT_NE(failure(binary).find("binary OFF is not supported"), std::string::npos)
      << failure(binary);
  // The same checks, and the others of the PLY header, on written files.
  struct Case {
    const char* file;
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"prop.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n",
       "a property before any element on line 3"},
      {"count.ply", "ply\nformat ascii 1.0\nelement vertex x\n",
       "an element without a name and count on line 3"},
      {"huge.ply",
       "ply\nformat ascii 1.0\nelement face 99999999999\nproperty list uchar int vertex_indices\n"
       "end_header\n",
       "absurd size"},
      {"liar.ply", "ply\nformat ascii 1.0\nelement vertex 1000\nproperty float x\nend_header\n0\n",
       "truncated: the header claims 1000 elements"},
      {"nohead.ply", "ply\nformat ascii 1.0\nelement vertex 1\n",
       "PLY header without \"end_header\""},
      {"notply.ply", "PLY\n", "no \"ply\" on the first line"},
      // CGAL's PLY reader dereferences a null float reader for a coordinate of another type.
      {"uchar.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty uchar z\nend_header\n0\n",
       "vertex coordinate z has type 'uchar' (expected float or double) on line 4"},
      // CGAL's OFF reader converts a face index read as a double to size_t.
      {"index.off",
       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2e33\n3 1 2 3\n",
       "absurd number '2e33' on line 9"},
      {"count.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n350542535 0 2 1\n",
       "truncated: the face on line 7 claims 350542535 vertices"},
      {"negindex.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 -4\n",
       "negative number '-4' in the face on line 7"},
      {"infindex.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 inf\n",
       "non-finite number on line 8"},
      {"comment.off", "COFF # colours\n# a comment line\nBINARY\n", "binary OFF is not supported"},
      {"ndim.off", "nOFF\n3\n4 4 0\n", "OFF variant 'nOFF' is not supported"},
      {"homog.off", "4OFF\n4 4 0\n", "OFF variant '4OFF' is not supported"},
  };
  for (const Case& c : cases) {
    const std::string msg = failure(writeFile(c.file, c.text));
    EXPECT_NE(msg.find(c.message), std::string::npos) << c.file << ": got \"" << msg << "\"";
  }
}

}  // namespace
}  // namespace grip::voxel::test
