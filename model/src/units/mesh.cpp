// Built-in closed meshes and mesh files through the one loader (units/mesh.hpp).
#include "rayunits/units/mesh.hpp"

#include <cmath>
#include <map>
#include <utility>

#include "rayunits/scene/mesh_file.hpp"
#include "rayunits/scene/scene.hpp"

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

// The one mesh-file loader (scene/mesh_file.hpp) with the file's own coordinates (double) and
// vertex indices for OFF and OBJ; other formats (PLY, STL, ...) through Assimp, corners at
// identical positions joined into shared vertices. The same checks and error lines as every
// other command that takes a mesh.
Mesh load_mesh(const std::string& path) {
  ru::scene::MeshFile f;
  try {
    f = ru::scene::read_mesh_file(path, ru::scene::MeshCoordinates::Exact);
  } catch (const ru::scene::SceneError& e) {
    throw MeshError(e.what());
  }
  Mesh m;
  m.name = path;
  m.verts.reserve(f.verts.size());
  for (const auto& v : f.verts) m.verts.push_back({v.x, v.y, v.z});
  m.tris.reserve(f.tris.size());
  for (const auto& t : f.tris)
    m.tris.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
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
