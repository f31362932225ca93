// Mesh loading through the one loader (Assimp behind it): formats, errors, limits, topology,
// and a fuzz test of the loader path (the larger one: test_mesh_fuzz.cpp).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "rayunits/scene/mesh_file.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/units/mesh.hpp"

using namespace ru::scene;

namespace {

std::string temp_dir() {
  static char made[64] = "";  // plain storage: still valid when the atexit handler runs
  static std::string dir = [] {
    char tmpl[] = "/tmp/ru-loader-XXXXXX";
    const char* d = mkdtemp(tmpl);
    if (!d) return std::string("/tmp");
    std::snprintf(made, sizeof made, "%s", d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(made, ec);
    });
    return std::string(d);
  }();
  return dir;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  std::string p = temp_dir() + "/" + name;
  std::ofstream f(p, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return p;
}

// A unit square in the plane z = 2 (two triangles) in four formats; y-up files store it
// with y = 2 so that the z-up conversion (x, y, z) -> (x, -z, y) gives the same square.
const char* kObj = "v 0 0 2\nv 1 0 2\nv 1 1 2\nv 0 1 2\nf 1 2 3\nf 1 3 4\n";
const char* kOff = "OFF\n4 2 0\n0 0 2\n1 0 2\n1 1 2\n0 1 2\n3 0 1 2\n3 0 2 3\n";
const char* kPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 2\n1 0 2\n1 1 2\n0 1 2\n3 0 1 2\n3 0 2 3\n";
const char* kStl =
    "solid sq\nfacet normal 0 0 1\nouter loop\nvertex 0 0 2\nvertex 1 0 2\nvertex 1 1 2\nendloop\nendfacet\n"
    "facet normal 0 0 1\nouter loop\nvertex 0 0 2\nvertex 1 1 2\nvertex 0 1 2\nendloop\nendfacet\nendsolid sq\n";

void expect_one_line_scene_error(const std::string& path) {
  try {
    Scene s = load_mesh(path, 'z');
    // Accepted input: it must then be a usable scene.
    EXPECT_FALSE(s.tris.empty());
    for (const auto& t : s.tris)
      for (const auto& p : t.p) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  } catch (const SceneError& e) {
    std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find(path), std::string::npos) << m;  // names the file
  }
  // Any other exception type propagates and fails the test; a crash fails the suite.
}

}  // namespace

TEST(Loader, FourFormatsGiveTheSameSquare) {
  for (auto [name, text] : {std::pair{"sq.obj", kObj}, {"sq.off", kOff}, {"sq.ply", kPly}, {"sq.stl", kStl}}) {
    SCOPED_TRACE(name);
    Scene s = load_mesh(write_file(name, text), 'z');
    ASSERT_EQ(s.tris.size(), 2u);
    double area = 0;
    for (const auto& t : s.tris) {
      for (const auto& p : t.p) {
        EXPECT_EQ(p.z, 2.0);
        EXPECT_TRUE(p.x == 0 || p.x == 1);
        EXPECT_TRUE(p.y == 0 || p.y == 1);
      }
      area += 0.5 * std::fabs(cross(t.p[1] - t.p[0], t.p[2] - t.p[0]).z);
    }
    EXPECT_EQ(area, 1.0);
    EXPECT_EQ(s.bounds_lo(), (Vec3{0, 0, 2}));
    EXPECT_EQ(s.bounds_hi(), (Vec3{1, 1, 2}));
  }
}

TEST(Loader, YUpIsTurnedExactly) {
  Scene s = load_mesh(write_file("y.obj", "v 0.1 0.2 0.3\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), 'y');
  ASSERT_EQ(s.tris.size(), 1u);
  EXPECT_EQ(s.tris[0].p[0], (Vec3{0.1f, -0.3f, 0.2f}));  // Assimp stores float coordinates
}

TEST(Loader, ErrorsAreOneLine) {
  auto msg = [](const std::string& path) {
    try {
      load_mesh(path);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(msg("/nonexistent/dir/x.obj").find("no such file"), std::string::npos);
  EXPECT_NE(msg(temp_dir()).find("no such file"), std::string::npos);  // a directory
  std::string empty = write_file("empty.obj", "");
  std::string m = msg(empty);
  EXPECT_NE(m, "(no error)");
  EXPECT_EQ(m.find('\n'), std::string::npos);
  // Points only: no triangles.
  m = msg(write_file("points.obj", "v 0 0 0\nv 1 0 0\np 1\np 2\n"));
  EXPECT_NE(m, "(no error)");
  EXPECT_EQ(m.find('\n'), std::string::npos);
  // Unknown extension with garbage.
  m = msg(write_file("junk.xyzzy", "\x01\x02garbage"));
  EXPECT_NE(m, "(no error)");
  EXPECT_THROW(load_mesh(write_file("ok.obj", kObj), 'x'), SceneError);
}

// Truncations and random byte corruptions of valid files in every format: the loader either
// returns a usable scene or throws one SceneError line; it never crashes or throws anything else.
TEST(Loader, FuzzTruncatedAndCorruptedFiles) {
  set_mesh_load_timeout(5.0);  // a hang inside the importer becomes an error after 5 s
  std::mt19937 rng(12345);
  int loaded = 0, rejected = 0;
  for (auto [ext, text] : {std::pair{"obj", kObj}, {"off", kOff}, {"ply", kPly}, {"stl", kStl}}) {
    const std::string base = text;
    for (size_t cut = 0; cut < base.size(); cut += 3) {
      std::string p = write_file(std::string("cut.") + ext, base.substr(0, cut));
      expect_one_line_scene_error(p);
    }
    for (int i = 0; i < 40; ++i) {
      std::string s = base;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < flips; ++k) s[rng() % s.size()] = static_cast<char>(rng() % 256);
      std::string p = write_file(std::string("flip.") + ext, s);
      try {
        load_mesh(p, 'z');
        ++loaded;
      } catch (const SceneError&) {
        ++rejected;
      }
      expect_one_line_scene_error(p);
    }
  }
  set_mesh_load_timeout(0);
  // Both outcomes occur (the corruption is neither always harmless nor always fatal).
  EXPECT_GT(loaded, 0);
  EXPECT_GT(rejected, 0);
}

// The sandbox turns an importer hang into an error line: a PLY header cut short (Assimp 5.2.5
// loops forever on it) is caught by the header check; the time limit catches the rest.
TEST(Loader, TruncatedPlyHeaderDoesNotHang) {
  std::string p = write_file("hang.ply", "ply\nformat ascii 1");
  try {
    load_mesh(p, 'z');
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("end_header"), std::string::npos) << e.what();
  }
}

TEST(Loader, NonFiniteCoordinatesAreRejected) {
  std::string p = write_file("nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
  try {
    load_mesh(p, 'z');
    SUCCEED() << "Assimp dropped the bad vertex";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  std::string q = write_file("inf.off", "OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n");
  try {
    Scene s = load_mesh(q, 'z');
    for (const auto& t : s.tris)
      for (const auto& v : t.p) EXPECT_TRUE(std::isfinite(v.x));
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

// Real meshes nobody here wrote (Debian assimp-testmodels / libcgal-demo), when installed.
TEST(Loader, DebianTestModels) {
  const char* cube = "/usr/share/assimp/models/OFF/Cube.off";
  struct stat st;
  if (::stat(cube, &st) != 0) GTEST_SKIP() << "assimp-testmodels not installed (scripts/install-deps.sh --long)";
  Scene s = load_mesh(cube, 'z');
  EXPECT_EQ(s.tris.size(), 12u);
  Vec3 ext = s.bounds_hi() - s.bounds_lo();
  EXPECT_GT(ext.x, 0);
  EXPECT_EQ(ext.x, ext.y);
  EXPECT_EQ(ext.y, ext.z);
}

TEST(LongLoader, AllDebianTestModelsLoadOrFailCleanly) {
  const char* dirs[] = {"/usr/share/assimp/models/OBJ", "/usr/share/assimp/models/OFF",
                        "/usr/share/assimp/models/PLY", "/usr/share/assimp/models/STL"};
  struct stat st;
  if (::stat(dirs[0], &st) != 0) GTEST_SKIP() << "assimp-testmodels not installed";
  int n = 0;
  for (const char* d : dirs) {
    std::string cmd = std::string("ls ") + d;
    FILE* p = popen(cmd.c_str(), "r");
    char line[512];
    while (p && fgets(line, sizeof line, p)) {
      std::string f = std::string(d) + "/" + std::string(line, strcspn(line, "\n"));
      SCOPED_TRACE(f);
      expect_one_line_scene_error(f);
      ++n;
    }
    if (p) pclose(p);
  }
  EXPECT_GT(n, 20);
  std::string bunny = find_demo_mesh("bunny");
  if (!bunny.empty()) {
    EXPECT_EQ(load_mesh(bunny).tris.size(), 75408u);
  }
}

// --- The one loader (scene/mesh_file.hpp), issue 12 §7 ---------------------------------------

namespace {

// The closed octahedron: 6 vertices, 8 outward triangles.
const char* kOctaOff =
    "OFF\n6 8 12\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
    "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";

std::string octa_stl() {
  const double v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  std::string s = "solid o\n";
  for (const auto& t : f) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (int k : t) s += "vertex " + std::to_string(v[k][0]) + " " + std::to_string(v[k][1]) + " " + std::to_string(v[k][2]) + "\n";
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid o\n";
}

std::string both_errors(const std::string& path) {
  std::string a = "(accepted)", b = "(accepted)";
  try {
    load_mesh(path, 'z');
  } catch (const SceneError& e) {
    a = e.what();
  }
  try {
    ru::units::load_mesh(path);
  } catch (const ru::units::MeshError& e) {
    b = e.what();
  }
  EXPECT_EQ(a, b) << "every command gets the same error line";
  return a;
}

}  // namespace

// The two files of the issue: a header claiming 999,999,999 vertices is rejected from its size
// before anything is allocated; a face using vertex 7 of 3 is rejected by render and by the
// watertightness study with the same line.
TEST(Loader, IssueExamplesAreRejectedByEveryEntryPoint) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string m = both_errors(write_file("huge.off", "OFF\n999999999 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_NE(m.find("huge.off:2: the OFF header claims 999999999 vertices and 1 faces, more than a file of 44 bytes"),
            std::string::npos) << m;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  m = both_errors(write_file("idx7.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
  EXPECT_NE(m.find("idx7.off:6: face 0: vertex index 7 out of range (the file has 3 vertices: 0..2)"), std::string::npos) << m;
  m = both_errors(write_file("idx7.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 8\n"));
  EXPECT_NE(m.find("idx7.obj:4: vertex index 8 out of range"), std::string::npos) << m;
  m = both_errors(write_file("idx7.ply",
                             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
  EXPECT_NE(m.find("vertex index 7 out of range"), std::string::npos) << m;
}

TEST(Loader, CountsAreCheckedAgainstTheFileSize) {
  std::string m = both_errors(write_file(
      "big.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 999999999\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                     std::string(60, '\0')));
  EXPECT_NE(m.find("the header claims 999999999 vertex, 1 face elements, more than the 60 bytes"), std::string::npos) << m;
  std::string stl(84, '\0');
  stl[80] = '\xff';
  stl[81] = '\xff';
  stl[82] = '\xff';
  m = both_errors(write_file("big.stl", stl));
  EXPECT_NE(m.find("as binary STL it claims 16777215 triangles"), std::string::npos) << m;
  m = both_errors(write_file("short.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  EXPECT_NE(m.find("the file ends after 1 of the 2 faces its header claims"), std::string::npos) << m;
}

// The importer's address space is limited (RLIMIT_AS in the child): an import that needs more
// than the limit gives one error line, however small its result (here 300,000 vertices, one
// triangle: Assimp holds the file and every vertex, the reply is one triangle).
TEST(Loader, MemoryLimitStopsTheImporter) {
  std::string off = "OFF\n300000 1 0\n0 0 0\n1 0 0\n0 1 0\n";
  for (int i = 3; i < 300000; ++i) off += "0 0 0\n";
  off += "3 0 1 2\n";
  const std::string p = write_file("mem.off", off);
  ru::scene::set_mesh_memory_limit_mb(2);
  std::string m;
  try {
    load_mesh(p, 'z');
  } catch (const SceneError& e) {
    m = e.what();
  }
  ru::scene::set_mesh_memory_limit_mb(0);
  EXPECT_NE(m.find("the import needs more than its memory limit of 2 MiB (malformed file? RU_MESH_MEMORY_MB raises"),
            std::string::npos) << m;
  EXPECT_EQ(load_mesh(p, 'z').tris.size(), 1u);  // the default limit serves
}

TEST(Loader, CoordinatesMustBeFiniteAndNotHuge) {
  for (const char* bad : {"nan", "inf", "1e999", "-1e20", "18446744073709551617e1"}) {
    SCOPED_TRACE(bad);
    const std::string m =
        both_errors(write_file("c.off", std::string("OFF\n3 1 0\n0 0 0\n1 0 ") + bad + "\n0 1 0\n3 0 1 2\n"));
    EXPECT_NE(m.find("c.off:4: vertex 1 has the"), std::string::npos) << m;
    EXPECT_NE(m.find("accepted: finite numbers of magnitude at most 2^64"), std::string::npos) << m;
  }
  // Exactly 2^64 is accepted.
  EXPECT_EQ(load_mesh(write_file("max.off", "OFF\n3 1 0\n0 0 0\n1 0 18446744073709551616\n0 1 0\n3 0 1 2\n"), 'z').tris.size(), 1u);
  // Binary formats are checked after the import: a binary STL with an infinite coordinate.
  std::string stl(80, ' ');
  uint32_t n = 1;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  const float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, INFINITY, 1, 0};
  stl.append(reinterpret_cast<const char*>(tri), sizeof tri);
  stl.append(2, '\0');
  const std::string m = both_errors(write_file("inf.stl", stl));
  EXPECT_NE(m.find("has a non-finite coordinate"), std::string::npos) << m;
}

// Faces with two corners on one vertex have no area and no edge of the surface: dropped and
// counted; the rest of a closed mesh stays closed for the watertightness study.
TEST(Loader, DegenerateFacesAreDroppedAndCounted) {
  ASSERT_EQ(std::string(kOctaOff).substr(0, 10), "OFF\n6 8 12");
  const std::string p = write_file("degen.off", std::string(kOctaOff).replace(6, 1, "9") + "3 0 0 1\n");
  for (auto mode : {ru::scene::MeshCoordinates::Importer, ru::scene::MeshCoordinates::Exact}) {
    const ru::scene::MeshFile f = ru::scene::read_mesh_file(p, mode);
    EXPECT_EQ(f.tris.size(), 8u);
    EXPECT_EQ(f.dropped_degenerate, 1u);
  }
  EXPECT_EQ(ru::units::closed_mesh_edges(ru::units::load_mesh(p)).size(), 12u);
  const std::string m = both_errors(write_file("alldegen.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 0 1\n3 1 2 2\n"));
  EXPECT_NE(m.find("alldegen.off: no triangles (all 2 have two corners on one vertex)"), std::string::npos) << m;
}

// Indexed faces with the topology intact for every format: the triangle soup of an STL file is
// joined at identical positions, so the watertightness study finds the shared edges.
TEST(Loader, TopologyIsIndexedForEveryFormat) {
  const std::string stl = write_file("octa.stl", octa_stl());
  const ru::scene::MeshFile f = ru::scene::read_mesh_file(stl);
  EXPECT_EQ(f.verts.size(), 6u);
  EXPECT_EQ(f.tris.size(), 8u);
  const ru::units::Mesh m = ru::units::load_mesh(stl);
  EXPECT_EQ(m.verts.size(), 6u);
  EXPECT_EQ(ru::units::closed_mesh_edges(m).size(), 12u);
  const ru::scene::MeshFile o = ru::scene::read_mesh_file(write_file("octa.off", kOctaOff));
  EXPECT_EQ(o.verts.size(), 6u);
  EXPECT_EQ(o.tris.size(), 8u);
}

// The study keeps the file's double coordinates (OFF/OBJ); scenes keep Assimp's binary32 ones.
TEST(Loader, ExactCoordinatesForTheStudyImporterCoordinatesForScenes) {
  const std::string p = write_file("tenth.off", "OFF\n3 1 0\n0.1 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(ru::units::load_mesh(p).verts[0].x, 0.1);
  EXPECT_EQ(load_mesh(p, 'z').tris[0].p[0].x, static_cast<double>(0.1f));
  // A coordinate is the number at the start of its token, as Assimp reads it (its own test model
  // OBJ/number_formats.obj has "3.1+e2"); a token without a number is an error.
  const std::string q = write_file("prefix.obj", "v 0 0 3.1+e2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(ru::units::load_mesh(q).verts[0].z, 3.1);
  EXPECT_EQ(load_mesh(q, 'z').tris[0].p[0].z, static_cast<double>(3.1f));
  const std::string m = both_errors(write_file("nonum.obj", "v 0 0 x3\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_NE(m.find("nonum.obj:1: 'x3' is not a number (expected 'v x y z')"), std::string::npos) << m;
}
