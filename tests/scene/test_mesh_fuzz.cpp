// Fuzz test of the one mesh loader (scene/mesh_file.hpp), issue 12 §7: >= 500 deterministic
// truncated, oversized, garbage and adversarial OBJ / OFF / PLY / STL files through both library
// entry points (ru::scene::load_mesh: render, study image, profile, bvh, trax; ru::units::load_mesh:
// study watertight), and a sample of them through every command that takes a mesh, as a user
// runs it. No crash, no hang, no signal; a rejected file gives exit status 2 and one error line;
// every planted error (index out of range, non-finite or huge coordinate, oversized count,
// degenerate-only mesh, short face, truncated count) is rejected.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rayunits/scene/mesh_file.hpp"
#include "rayunits/scene/scene.hpp"
#include "rayunits/units/mesh.hpp"
#include "rayunits/util/process.hpp"

namespace fs = std::filesystem;
using ru::scene::SceneError;

namespace {

enum class Expect { Any, Reject, Accept };

struct Case {
  std::string name;   // file name (extension picks the format)
  std::string bytes;
  Expect expect = Expect::Any;
  std::string why;    // what was planted
};

// The closed octahedron (6 vertices, 8 outward triangles) in every format.
const double kV[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
const int kF[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// Text writers with hooks: coordinate text, index text, header counts.
struct Text {
  std::vector<std::vector<std::string>> v;  // coordinates as text
  std::vector<std::vector<std::string>> f;  // indices as text (0-based values, writers adjust)
  Text() {
    for (const auto& p : kV) v.push_back({num(p[0]), num(p[1]), num(p[2])});
    for (const auto& t : kF) f.push_back({std::to_string(t[0]), std::to_string(t[1]), std::to_string(t[2])});
  }
};

// The body OFF and ASCII PLY share: "x y z" per vertex, then "n i0 i1 ..." per face.
std::string vertex_face_lines(const Text& t) {
  std::string s;
  for (const auto& p : t.v) s += p[0] + " " + p[1] + " " + p[2] + "\n";
  for (const auto& f : t.f) {
    s += std::to_string(f.size());
    for (const auto& i : f) s += " " + i;
    s += "\n";
  }
  return s;
}

std::string off(const Text& t, const std::string& counts = "") {
  std::string s = "OFF\n" + (counts.empty() ? std::to_string(t.v.size()) + " " + std::to_string(t.f.size()) + " 12" : counts) + "\n";
  return s + vertex_face_lines(t);
}

// OBJ indices are 1-based: the writer adds 1 to plain numbers, other text goes through as is.
std::string obj(const Text& t, bool raw_indices = false) {
  std::string s = "# octahedron\n";
  for (const auto& p : t.v) s += "v " + p[0] + " " + p[1] + " " + p[2] + "\n";
  for (const auto& f : t.f) {
    s += "f";
    for (const auto& i : f) s += " " + (raw_indices ? i : std::to_string(std::stoll(i) + 1));
    s += "\n";
  }
  return s;
}

std::string ply_ascii(const Text& t, const std::string& nv = "", const std::string& nf = "") {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + (nv.empty() ? std::to_string(t.v.size()) : nv) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  (nf.empty() ? std::to_string(t.f.size()) : nf) + "\nproperty list uchar int vertex_indices\nend_header\n";
  return s + vertex_face_lines(t);
}

template <class V>
void put(std::string* s, V v) {
  s->append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::string ply_binary(const std::vector<std::array<float, 3>>& v, const std::vector<std::array<int32_t, 3>>& f,
                       uint64_t nv_claim = 0, uint64_t nf_claim = 0) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(nv_claim ? nv_claim : v.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                  std::to_string(nf_claim ? nf_claim : f.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : v)
    for (float c : p) put(&s, c);
  for (const auto& t : f) {
    put(&s, uint8_t{3});
    for (int32_t i : t) put(&s, i);
  }
  return s;
}

std::string stl_ascii(const Text& t) {
  std::string s = "solid octa\n";
  for (const auto& f : t.f) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (const auto& i : f) {
      const auto& p = t.v[static_cast<size_t>(std::stoll(i))];
      s += "vertex " + p[0] + " " + p[1] + " " + p[2] + "\n";
    }
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid octa\n";
}

std::string stl_binary(const std::vector<std::array<std::array<float, 3>, 3>>& tris, int64_t claim = -1) {
  std::string s(80, ' ');
  s.replace(0, 10, "binary stl");
  put(&s, static_cast<uint32_t>(claim >= 0 ? static_cast<uint64_t>(claim) : tris.size()));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put(&s, 0.0f);
    for (const auto& p : t)
      for (float c : p) put(&s, c);
    put(&s, uint16_t{0});
  }
  return s;
}

std::vector<std::array<float, 3>> octa_verts() {
  std::vector<std::array<float, 3>> v;
  for (const auto& p : kV) v.push_back({float(p[0]), float(p[1]), float(p[2])});
  return v;
}
std::vector<std::array<int32_t, 3>> octa_faces() {
  std::vector<std::array<int32_t, 3>> f;
  for (const auto& t : kF) f.push_back({t[0], t[1], t[2]});
  return f;
}
std::vector<std::array<std::array<float, 3>, 3>> octa_soup() {
  std::vector<std::array<std::array<float, 3>, 3>> s;
  auto v = octa_verts();
  for (const auto& t : kF) s.push_back({v[t[0]], v[t[1]], v[t[2]]});
  return s;
}

// Every case, deterministically (fixed seed).
std::vector<Case> make_cases() {
  std::vector<Case> out;
  std::mt19937_64 rng(20250612);
  auto add = [&](const std::string& name, std::string bytes, Expect e = Expect::Any, const std::string& why = "") {
    out.push_back({std::to_string(out.size()) + "_" + name, std::move(bytes), e, why});
  };
  const Text t;
  const std::vector<std::pair<std::string, std::string>> bases = {
      {"off", off(t)},
      {"obj", obj(t)},
      {"ply", ply_ascii(t)},
      {"ply", ply_binary(octa_verts(), octa_faces())},
      {"stl", stl_ascii(t)},
      {"stl", stl_binary(octa_soup())}};
  for (const auto& [ext, b] : bases) add("valid." + ext, b, Expect::Accept);

  // Truncations: 20 cut points per file, from the empty file to one byte short.
  for (const auto& [ext, b] : bases)
    for (int i = 0; i < 20; ++i) add("cut." + ext, b.substr(0, b.size() * i / 20), i == 0 ? Expect::Reject : Expect::Any);

  // Byte corruptions: 1..4 bytes replaced, half by random bytes, half by characters that
  // change the meaning of text files.
  const std::string meaningful = std::string("\0\n\r-+.e9#/ \xff", 12);
  for (const auto& [ext, b] : bases)
    for (int i = 0; i < 25; ++i) {
      std::string s = b;
      const int n = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < n; ++k)
        s[rng() % s.size()] = (i % 2) ? meaningful[rng() % meaningful.size()] : static_cast<char>(rng() & 0xff);
      add("flip." + ext, s);
    }

  // Oversized counts (the issue's 999,999,999-vertex OFF and its relatives).
  for (const char* c : {"999999999 8 12", "6 999999999 12", "4294967295 4294967295 0", "4294967296 8 0",
                        "18446744073709551615 8 0", "99999999999999999999999 8 0", "-1 8 0", "6 -8 0", "0 8 0", "6 0 0",
                        "7 8 12", "6 9 12", "6", "x y z"})
    add("count.off", off(t, c), Expect::Reject, std::string("OFF counts ") + c);
  for (auto [nv, nf] : {std::pair<const char*, const char*>{"999999999", ""}, {"", "999999999"}, {"4294967295", "4294967295"},
                        {"18446744073709551616", ""}, {"-6", ""}, {"7", ""}, {"", "9"}})
    add("count.ply", ply_ascii(t, nv, nf), Expect::Reject, std::string("PLY counts ") + nv + " " + nf);
  for (auto [nv, nf] : {std::pair<uint64_t, uint64_t>{999999999, 0}, {0, 999999999}, {4294967295u, 4294967295u}, {7, 0}, {0, 9}})
    add("count.ply", ply_binary(octa_verts(), octa_faces(), nv, nf), Expect::Reject, "binary PLY counts");
  for (int64_t c : {int64_t{999999999}, int64_t{4294967295}, int64_t{0}, int64_t{9}, int64_t{7}})
    add("count.stl", stl_binary(octa_soup(), c), Expect::Reject, "binary STL count " + std::to_string(c));

  // Garbage: random bytes and random mesh-like text under every extension.
  const char* exts[] = {"off", "obj", "ply", "stl"};
  for (const char* ext : exts)
    for (int i = 0; i < 20; ++i) {
      std::string s(rng() % 4096, '\0');
      for (char& c : s) c = static_cast<char>(rng() & 0xff);
      add(std::string("bytes.") + ext, s);
    }
  const char* words[] = {"v", "f", "vt", "vn", "OFF", "ply", "solid", "facet", "vertex", "endloop", "end_header",
                         "element", "property", "0", "1", "2", "3", "-1", "7", "1e999", "nan", "inf", "1/2/3",
                         "//", "#", "\n", "\n", "\n", "0.5", "-0", "4294967296", "format", "ascii", "list"};
  for (const char* ext : exts)
    for (int i = 0; i < 15; ++i) {
      std::string s;
      const int n = static_cast<int>(rng() % 300);
      for (int k = 0; k < n; ++k) s += std::string(words[rng() % (sizeof words / sizeof *words)]) + " ";
      add(std::string("words.") + ext, s);
    }

  // Adversarial files with one planted error each: must be rejected.
  auto with = [&](auto edit) {
    Text c = t;
    edit(c);
    return c;
  };
  for (const char* bad : {"6", "7", "106", "-1", "4294967296", "1.5", "x"}) {
    Text c = with([&](Text& x) { x.f[3][1] = bad; });
    add("index.off", off(c), Expect::Reject, std::string("OFF index ") + bad);
    add("index.ply", ply_ascii(c), Expect::Reject, std::string("PLY index ") + bad);
  }
  for (const char* bad : {"0", "7", "-7", "99", "1/5", "1//5", "1/1/1", "x", ""}) {
    Text c = with([&](Text& x) {
      for (auto& f : x.f)
        for (auto& i : f) i = std::to_string(std::stoll(i) + 1);  // OBJ is 1-based
      x.f[5][2] = bad;
    });
    add("index.obj", obj(c, true), Expect::Reject, std::string("OBJ index '") + bad + "'");
  }
  {
    auto f = octa_faces();
    f[2][0] = 6;
    add("index.ply", ply_binary(octa_verts(), f), Expect::Reject, "binary PLY index 6");
    f[2][0] = -1;
    add("index.ply", ply_binary(octa_verts(), f), Expect::Reject, "binary PLY index -1");
  }
  for (const char* bad : {"nan", "-nan", "inf", "-inf", "1e999", "-1e400", "1e20", "-3e38", "1e20x", "x1"}) {
    Text c = with([&](Text& x) { x.v[4][2] = bad; });
    const std::string why = std::string("coordinate ") + bad;
    add("coord.off", off(c), Expect::Reject, why);
    add("coord.obj", obj(c), Expect::Reject, why);
    if (std::string(bad).find('x') == std::string::npos) {  // tokens with letters: the OFF/OBJ readers' check
      add("coord.stl", stl_ascii(c), Expect::Reject, why);
      add("coord.ply", ply_ascii(c), Expect::Reject, why);
    }
  }
  for (float bad : {NAN, INFINITY, -INFINITY, 1e20f, -3e38f}) {
    auto v = octa_verts();
    v[4][2] = bad;
    add("coord.ply", ply_binary(v, octa_faces()), Expect::Reject, "binary PLY coordinate " + num(bad));
    auto s = octa_soup();
    s[1][2][2] = bad;
    add("coord.stl", stl_binary(s), Expect::Reject, "binary STL coordinate " + num(bad));
  }
  // Largest accepted magnitude: exactly 2^64 (float-representable) is fine.
  add("coordmax.off", off(with([](Text& x) { x.v[4][2] = "18446744073709551616"; })), Expect::Accept, "coordinate 2^64");
  // Degenerate faces: one among good ones is dropped (accepted), all of them: rejected.
  add("degen1.off", off(with([](Text& x) { x.f.push_back({"0", "0", "1"}); })), Expect::Accept, "one degenerate face");
  add("degenall.off", off(with([](Text& x) {
        for (auto& f : x.f) f[1] = f[0];
      })),
      Expect::Reject, "all faces degenerate");
  add("degenall.obj", obj(with([](Text& x) {
        for (auto& f : x.f) f[2] = f[1];
      })),
      Expect::Reject, "all faces degenerate");
  // Faces of one or two vertices.
  add("short.off", off(with([](Text& x) { x.f[0].resize(2); })), Expect::Reject, "OFF face of 2");
  add("short.obj", obj(with([](Text& x) { x.f[0].resize(1); })), Expect::Reject, "OBJ face of 1");
  // A PLY header cut short (Assimp 5.2.5 loops forever on it) and one without its end.
  add("hang.ply", "ply\nformat ascii 1", Expect::Reject, "PLY header cut short");
  add("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", Expect::Reject, "no end_header");
  // A line longer than 1 MiB.
  add("longline.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 " + std::string(1100000, '1') + "\n", Expect::Reject, "long line");
  // Binary zeros, only a header, only vertices.
  add("zeros.off", std::string(1000, '\0'), Expect::Reject, "zeros");
  add("zeros.stl", std::string(184, '\0'), Expect::Reject, "zeros (binary STL claiming 0 triangles)");
  add("header.off", "OFF\n6 8 12\n", Expect::Reject, "OFF header only");
  add("verts.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", Expect::Reject, "OBJ without faces");
  add("empty.obj", "", Expect::Reject, "empty");
  return out;
}

std::string temp_dir() {
  static std::string dir = [] {
    char tmpl[] = "/tmp/ru-meshfuzz-XXXXXX";
    const char* d = mkdtemp(tmpl);
    return std::string(d ? d : "/tmp");
  }();
  return dir;
}

std::string write_case(const Case& c) {
  const std::string p = temp_dir() + "/" + c.name;
  std::ofstream f(p, std::ios::binary);
  f.write(c.bytes.data(), static_cast<std::streamsize>(c.bytes.size()));
  return p;
}

struct Outcome {
  bool ok = false;
  std::string error;
};

template <class F>
Outcome attempt(F f) {
  Outcome o;
  try {
    f();
    o.ok = true;
  } catch (const SceneError& e) {
    o.error = e.what();
  } catch (const ru::units::MeshError& e) {
    o.error = e.what();
  }
  // Any other exception type escapes and fails the test; a crash fails the suite.
  return o;
}

void check_error_line(const std::string& m, const std::string& path) {
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_NE(m.find(path), std::string::npos) << "the error names the file: " << m;
  EXPECT_LT(m.size(), 700u) << m;
}

std::string rayunits() { return std::string(RU_BINARY_DIR) + "/model/cli/rayunits"; }

}  // namespace

TEST(MeshFuzz, FilesThroughBothLibraryEntryPointsAndEveryCommand) {
  const auto t0 = std::chrono::steady_clock::now();
  ru::scene::set_mesh_load_timeout(5.0);  // an importer hang becomes an error after 5 s
  const std::vector<Case> cases = make_cases();
  ASSERT_GE(cases.size(), 500u);
  int accepted = 0, rejected = 0;
  std::vector<std::pair<Case, std::string>> sample;  // for the commands
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::string p = write_case(c);
    SCOPED_TRACE(c.name + (c.why.empty() ? "" : " (" + c.why + ")"));
    ru::scene::Scene s;
    ru::units::Mesh m;
    const Outcome a = attempt([&] { s = ru::scene::load_mesh(p, 'z'); });
    const Outcome b = attempt([&] { m = ru::units::load_mesh(p); });
    // One loader: both entry points accept or reject the same file.
    EXPECT_EQ(a.ok, b.ok) << "scene: " << (a.ok ? "accepted" : a.error) << " | units: " << (b.ok ? "accepted" : b.error);
    if (c.expect == Expect::Reject) {
      EXPECT_FALSE(a.ok || b.ok) << "a planted error was accepted";
    }
    if (c.expect == Expect::Accept) {
      EXPECT_TRUE(a.ok && b.ok) << a.error << " | " << b.error;
    }
    if (!a.ok) check_error_line(a.error, p);
    if (!b.ok) check_error_line(b.error, p);
    if (a.ok) {
      ++accepted;
      EXPECT_FALSE(s.tris.empty());
      for (const auto& tri : s.tris) {
        EXPECT_LT(tri.material, s.materials.size());
        for (const auto& q : tri.p)
          for (double v : {q.x, q.y, q.z}) EXPECT_TRUE(std::isfinite(v) && std::fabs(v) <= ru::scene::kMaxMeshCoordinate);
        EXPECT_FALSE(tri.p[0] == tri.p[1] || tri.p[1] == tri.p[2] || tri.p[0] == tri.p[2]) << "degenerate kept";
      }
    } else {
      ++rejected;
    }
    if (b.ok) {
      for (const auto& tri : m.tris) {
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(tri[k], 0);
          EXPECT_LT(static_cast<size_t>(tri[k]), m.verts.size());
        }
        EXPECT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2]) << "degenerate kept";
      }
    }
    // The commands see every planted error, every valid file and every 12th other file.
    if (c.expect != Expect::Any || i % 12 == 0) sample.push_back({c, p});
  }
  ru::scene::set_mesh_load_timeout(0);
  EXPECT_GT(accepted, 20);
  EXPECT_GT(rejected, 300);
  const double lib_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Every command that takes a mesh, on a deterministic sample (the first few dozen of the above).
  ASSERT_GE(sample.size(), 30u);
  if (sample.size() > 40) {
    std::vector<std::pair<Case, std::string>> keep;
    for (size_t i = 0; i < sample.size(); ++i)
      if (i * 40 / sample.size() != (i + 1) * 40 / sample.size() || i == 0) keep.push_back(sample[i]);
    sample.swap(keep);
  }
  const std::string out = temp_dir() + "/out";
  ::setenv("RU_MESH_TIMEOUT", "5", 1);  // for the commands: an importer hang is an error after 5 s
  struct Cmd {
    const char* name;
    std::string args;  // {M}: the mesh, {O}: an output path
  };
  const std::vector<Cmd> cmds = {
      {"render", "render --mesh {M} --up z --size 8x8 --threads 1 --quiet --out {O}.png"},
      {"profile", "profile --mesh {M} --up z --size 4x4 --threads 1 --min-frac 8 --max-frac 9 --json {O}.json"},
      {"study watertight", "study watertight --mesh {M} --rays 4 --threads 1 --quiet --csv {O}.csv"},
      {"bvh", "bvh --mesh {M} --sa-iters 2 --cast-size 0 --csv {O}.csv"},
      {"trax", "trax --mesh {M} --up z --size 2x2 --out {O}.d"},
  };
  int runs = 0, cli_ok = 0, cli_rejected = 0;
  for (const auto& [c, p] : sample) {
    for (const auto& cmd : cmds) {
      SCOPED_TRACE(std::string(cmd.name) + " " + c.name + (c.why.empty() ? "" : " (" + c.why + ")"));
      const std::string o = out + std::to_string(runs);
      // Words of the command line, {M} and {O} filled in (no shell: the util launcher).
      std::vector<std::string> argv = {rayunits()};
      std::istringstream words(cmd.args);
      for (std::string w; words >> w;) {
        if (w == "{M}") w = p;
        const size_t at = w.find("{O}");
        if (at != std::string::npos) w.replace(at, 3, o);
        argv.push_back(w);
      }
      ru::util::ProcessOptions po;
      po.timeout_s = 60;
      po.out = ru::util::Redirect::null();
      po.err = ru::util::Redirect::capture();
      const ru::util::ProcessResult r = ru::util::run_process(argv, po);
      ++runs;
      const std::string line = ru::util::shell_join(argv);
      ASSERT_TRUE(r.started) << r.error << ": " << line;
      ASSERT_FALSE(r.timed_out) << "hang: " << line;
      ASSERT_EQ(r.term_signal, 0) << "killed by signal " << r.term_signal << ": " << line << "\n" << r.err;
      const int rc = r.exit_code;
      const std::string& e = r.err;
      ASSERT_TRUE(rc == 0 || rc == 2) << "exit " << rc << ": " << line << "\n" << e;
      if (c.expect == Expect::Reject) {
        EXPECT_EQ(rc, 2) << "a planted error was accepted: " << line;
      }
      if (rc == 2) {
        ++cli_rejected;
        // One error line (warnings about dropped faces may precede it), nothing written.
        std::vector<std::string> lines;
        std::stringstream ss(e);
        for (std::string l; std::getline(ss, l);) lines.push_back(l);
        ASSERT_FALSE(lines.empty()) << line;
        EXPECT_EQ(lines.back().rfind(std::string("rayunits ") + cmd.name + ": error: ", 0), 0u) << e;
        for (size_t k = 0; k + 1 < lines.size(); ++k)
          EXPECT_EQ(lines[k].rfind("rayunits: warning: ", 0), 0u) << e;
        for (const char* suffix : {".png", ".json", ".csv", ".d"}) EXPECT_FALSE(fs::exists(o + suffix)) << o << suffix;
      } else {
        ++cli_ok;
        if (std::string(cmd.name) == "render") {
          EXPECT_TRUE(fs::exists(o + ".png"));
        }
      }
    }
  }
  ::unsetenv("RU_MESH_TIMEOUT");
  EXPECT_GT(cli_ok, 0);
  EXPECT_GT(cli_rejected, 0);
  const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[mesh fuzz] %zu files (%d accepted, %d rejected) through both library entry points in %.1f s; "
              "%zu files x %zu commands = %d runs (%d exit 0, %d exit 2); total %.1f s\n",
              cases.size(), accepted, rejected, lib_s, sample.size(), cmds.size(), runs, cli_ok, cli_rejected, total_s);
  // No time limit here: a wall-clock assertion fails on a loaded machine (it did, 65 s beside a
  // Verilator build); speed targets live in benchmarks. Hangs are caught by the per-run timeouts.
  std::error_code ec;
  fs::remove_all(temp_dir(), ec);
}
