// rayunits units: small closed triangle meshes for the watertightness study, and mesh files
// through the project's one loader (scene/mesh_file.hpp).
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayunits/units/vec.hpp"

namespace ru::units {

class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Mesh {
  std::string name;
  std::vector<Vec3d> verts;
  std::vector<std::array<int, 3>> tris;  // counter-clockwise seen from outside
};

// Built-in closed meshes (all consistently oriented, outward normals):
//   icosphere: icosahedron subdivided `level` times, vertices on the unit sphere;
//   uvsphere:  latitude/longitude sphere, poles shared by `segments` triangles (high-valence
//              vertices);
//   torus:     major radius R, minor radius r, nu x nv quads split in two;
//   cube:      [-1,1]^3 with n x n quads per face, shared edges along the cube's creases.
Mesh make_icosphere(int level);
Mesh make_uvsphere(int rings, int segments);
Mesh make_torus(int nu, int nv, double R, double r);
Mesh make_cube(int n);

// "icosphere" (level 3), "icosphere4", "uvsphere" (24 x 48), "torus" (48 x 24, R 3, r 1),
// "cube" (8 x 8 per face). Throws MeshError naming the accepted scenes.
Mesh builtin_mesh(const std::string& name);
const char* builtin_mesh_names();  // "icosphere, icosphere4, uvsphere, torus, cube"

// A mesh file through ru::scene::read_mesh_file (MeshCoordinates::Exact): OBJ and OFF with
// their own double coordinates and vertex indices, polygons fan-triangulated; PLY, STL, ...
// through Assimp with corners at identical positions joined. Triangles with two corners on one
// vertex are dropped (counted warning). Throws MeshError (one line, file and line number).
Mesh load_mesh(const std::string& path);

struct MeshEdge {
  int v0, v1;   // v0 < v1
  int tri[2];   // the two triangles sharing it
};
// The edges of a closed, consistently oriented 2-manifold mesh: every edge used by exactly
// two triangles in opposite directions. Throws MeshError otherwise (naming the first bad edge).
std::vector<MeshEdge> closed_mesh_edges(const Mesh& m);

}  // namespace ru::units
