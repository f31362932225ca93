// Built-in closed meshes and a simple OBJ/OFF loader (units/mesh.hpp).
#include "rayunits/units/mesh.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

namespace ru::units {
namespace {

Vec3d normalized(const Vec3d& v) {
  const double n = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / n, v.y / n, v.z / n};
}

}  // namespace

Mesh make_icosphere(int level) {
  Mesh m;
  m.name = "icosphere" + std::to_string(level);
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& p : v) m.verts.push_back(normalized({p[0], p[1], p[2]}));
  m.tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
            {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const Vec3d& p = m.verts[a];
      const Vec3d& q = m.verts[b];
      m.verts.push_back(normalized({(p.x + q.x) / 2, (p.y + q.y) / 2, (p.z + q.z) / 2}));
      const int idx = static_cast<int>(m.verts.size()) - 1;
      mid[key] = idx;
      return idx;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& f : m.tris) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    m.tris = std::move(next);
  }
  return m;
}

Mesh make_uvsphere(int rings, int segments) {
  Mesh m;
  m.name = "uvsphere";
  m.verts.push_back({0, 0, 1});  // north pole
  for (int i = 1; i < rings; ++i) {
    const double th = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double ph = 2 * M_PI * j / segments;
      m.verts.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
  }
  m.verts.push_back({0, 0, -1});  // south pole
  const int south = static_cast<int>(m.verts.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) m.tris.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
      m.tris.push_back({a, c, d});
      m.tris.push_back({a, d, b});
    }
  for (int j = 0; j < segments; ++j) m.tris.push_back({south, ring(rings - 1, j + 1), ring(rings - 1, j)});
  return m;
}

Mesh make_torus(int nu, int nv, double R, double r) {
  Mesh m;
  m.name = "torus";
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * M_PI * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2 * M_PI * j / nv;
      m.verts.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.tris.push_back({a, b, c});
      m.tris.push_back({a, c, d});
    }
  return m;
}

Mesh make_cube(int n) {
  Mesh m;
  m.name = "cube";
  std::map<std::array<int, 3>, int> index;  // integer grid coordinates -> vertex
  auto vert = [&](std::array<int, 3> g) {
    auto it = index.find(g);
    if (it != index.end()) return it->second;
    m.verts.push_back({-1.0 + 2.0 * g[0] / n, -1.0 + 2.0 * g[1] / n, -1.0 + 2.0 * g[2] / n});
    const int idx = static_cast<int>(m.verts.size()) - 1;
    index[g] = idx;
    return idx;
  };
  // Face with fixed axis `ax` at grid value `side` (0 or n), outward normal sign s.
  for (int ax = 0; ax < 3; ++ax)
    for (int side : {0, n}) {
      const int u = (ax + 1) % 3, v = (ax + 2) % 3;
      const bool flip = side == 0;  // (u, v, ax) is right-handed: +ax face is CCW in (u, v)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto g = [&](int di, int dj) {
            std::array<int, 3> p{};
            p[ax] = side;
            p[u] = i + di;
            p[v] = j + dj;
            return vert(p);
          };
          const int a = g(0, 0), b = g(1, 0), c = g(1, 1), d = g(0, 1);
          if (!flip) {
            m.tris.push_back({a, b, c});
            m.tris.push_back({a, c, d});
          } else {
            m.tris.push_back({a, c, b});
            m.tris.push_back({a, d, c});
          }
        }
    }
  return m;
}

const char* builtin_mesh_names() { return "icosphere, icosphere4, uvsphere, torus, cube"; }

Mesh builtin_mesh(const std::string& name) {
  if (name == "icosphere") return make_icosphere(3);
  if (name == "icosphere4") return make_icosphere(4);
  if (name == "uvsphere") return make_uvsphere(24, 48);
  if (name == "torus") return make_torus(48, 24, 3.0, 1.0);
  if (name == "cube") return make_cube(8);
  throw MeshError("unknown scene '" + name + "' (built-in scenes: " + builtin_mesh_names() + ")");
}

namespace {

int parse_index(const std::string& tok, int nverts, const std::string& where) {
  const std::string head = tok.substr(0, tok.find('/'));
  char* end = nullptr;
  const long v = std::strtol(head.c_str(), &end, 10);
  if (head.empty() || *end != '\0' || v == 0)
    throw MeshError(where + ": bad vertex index '" + tok + "'");
  const long idx = v > 0 ? v - 1 : nverts + v;
  if (idx < 0 || idx >= nverts)
    throw MeshError(where + ": vertex index " + std::to_string(v) + " out of range (1.." + std::to_string(nverts) + ")");
  return static_cast<int>(idx);
}

void add_polygon(Mesh& m, const std::vector<int>& poly, const std::string& where) {
  if (poly.size() < 3) throw MeshError(where + ": a face needs at least 3 vertices");
  for (size_t i = 1; i + 1 < poly.size(); ++i) m.tris.push_back({poly[0], poly[i], poly[i + 1]});
}

}  // namespace

Mesh load_mesh(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MeshError("mesh " + path + ": cannot open");
  Mesh m;
  m.name = path;
  const bool off = path.size() >= 4 && (path.substr(path.size() - 4) == ".off" || path.substr(path.size() - 4) == ".OFF");
  const bool obj = path.size() >= 4 && (path.substr(path.size() - 4) == ".obj" || path.substr(path.size() - 4) == ".OBJ");
  if (!off && !obj) throw MeshError("mesh " + path + ": unknown extension (accepted: .obj, .off)");
  std::string line;
  int lineno = 0;
  auto where = [&] { return "mesh " + path + ":" + std::to_string(lineno); };
  if (obj) {
    while (std::getline(in, line)) {
      ++lineno;
      std::istringstream ss(line);
      std::string tag;
      if (!(ss >> tag) || tag[0] == '#') continue;
      if (tag == "v") {
        Vec3d v;
        if (!(ss >> v.x >> v.y >> v.z)) throw MeshError(where() + ": expected 'v x y z'");
        m.verts.push_back(v);
      } else if (tag == "f") {
        std::vector<int> poly;
        std::string tok;
        while (ss >> tok) poly.push_back(parse_index(tok, static_cast<int>(m.verts.size()), where()));
        add_polygon(m, poly, where());
      }
    }
  } else {
    auto next_line = [&]() -> std::string {
      while (std::getline(in, line)) {
        ++lineno;
        const size_t h = line.find('#');
        if (h != std::string::npos) line.resize(h);
        if (line.find_first_not_of(" \t\r") != std::string::npos) return line;
      }
      throw MeshError(where() + ": unexpected end of file");
    };
    std::string head = next_line();
    std::istringstream hs(head);
    std::string magic;
    hs >> magic;
    long nv = -1, nf = -1;
    if (magic != "OFF") throw MeshError(where() + ": expected OFF header");
    if (!(hs >> nv >> nf)) {
      std::istringstream cs(next_line());
      if (!(cs >> nv >> nf)) throw MeshError(where() + ": expected vertex and face counts");
    }
    if (nv < 0 || nf < 0) throw MeshError(where() + ": negative counts");
    for (long i = 0; i < nv; ++i) {
      std::istringstream ss(next_line());
      Vec3d v;
      if (!(ss >> v.x >> v.y >> v.z)) throw MeshError(where() + ": expected 'x y z'");
      m.verts.push_back(v);
    }
    for (long i = 0; i < nf; ++i) {
      std::istringstream ss(next_line());
      long n;
      if (!(ss >> n) || n < 3) throw MeshError(where() + ": expected a face 'n i0 i1 ...' with n >= 3");
      std::vector<int> poly;
      for (long k = 0; k < n; ++k) {
        long idx;
        if (!(ss >> idx) || idx < 0 || idx >= nv) throw MeshError(where() + ": bad vertex index");
        poly.push_back(static_cast<int>(idx));
      }
      add_polygon(m, poly, where());
    }
  }
  if (m.tris.empty()) throw MeshError("mesh " + path + ": no faces");
  return m;
}

std::vector<MeshEdge> closed_mesh_edges(const Mesh& m) {
  // Directed edge (a, b) -> triangle. A closed oriented manifold has every directed edge once
  // and its reverse once.
  std::map<std::pair<int, int>, int> dir;
  for (size_t t = 0; t < m.tris.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      const int a = m.tris[t][e], b = m.tris[t][(e + 1) % 3];
      if (a == b) throw MeshError(m.name + ": triangle " + std::to_string(t) + " repeats a vertex");
      if (!dir.emplace(std::make_pair(a, b), static_cast<int>(t)).second)
        throw MeshError(m.name + ": directed edge " + std::to_string(a) + "->" + std::to_string(b) +
                        " used twice (inconsistent orientation or non-manifold)");
    }
  std::vector<MeshEdge> out;
  for (const auto& [e, t] : dir) {
    auto it = dir.find({e.second, e.first});
    if (it == dir.end())
      throw MeshError(m.name + ": edge " + std::to_string(e.first) + "-" + std::to_string(e.second) +
                      " has one triangle (the mesh is not closed)");
    if (e.first < e.second) out.push_back({e.first, e.second, {t, it->second}});
  }
  return out;
}

}  // namespace ru::units
