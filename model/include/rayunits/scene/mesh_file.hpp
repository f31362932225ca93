// The one mesh-file loader: every command that takes a mesh file (render, study image, profile,
// bench render, bvh, trax, study trax, bench trax, study watertight) reads it through
// read_mesh_file, so every command accepts and rejects the same files with the same error line.
//
// What it does, in order (docs/RENDER.md, "Mesh files"):
//  1. The file must exist, be a regular file and be readable.
//  2. A parent-side reader checks the file before any importer sees it: OFF and OBJ are read
//     completely (counts against the file size before anything is allocated, every vertex
//     index in range, coordinates finite and at most kMaxMeshCoordinate in magnitude, faces
//     of at least three vertices; errors name the line); PLY and binary STL headers are checked
//     (element counts against the file size, a PLY header must end).
//  3. Assimp imports the file in a forked child process with a time limit and a memory limit
//     (RLIMIT_AS: 2 GiB above the parent's address space, RU_MESH_MEMORY_MB overrides), so a
//     hang, a crash or a runaway allocation inside the importer becomes one error line.
//  4. The triangles are joined into an indexed mesh (corners at bit-identical positions share
//     one vertex: the topology the watertightness study needs, for every format), checked
//     again (finite, not huge), and faces with two corners on one vertex (zero area, not part of
//     the surface) are dropped with one counted warning on stderr.
// Every error is one SceneError line naming the file and what is accepted.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rayunits/scene/vec.hpp"

namespace ru::scene {

// Largest accepted |coordinate|: 2^64. Beyond it the square of a coordinate overflows binary32
// (the widest hardware format studied) and e7m16 cannot hold the value at all; in practice such
// numbers in a mesh file are corruption.
constexpr double kMaxMeshCoordinate = 18446744073709551616.0;

// Where the vertex coordinates come from.
enum class MeshCoordinates {
  // Assimp's (binary32) coordinates and triangulation, for every format: what the renderer has
  // always used (its images stay bit-identical).
  Importer,
  // OFF and OBJ: the parent-side reader's coordinates (strtod, double) and fan triangulation,
  // with the file's own vertex indices (what the watertightness study has always read: exact
  // for e11m52); other formats fall back to Importer. The importer still runs and must accept
  // the file, so that both modes accept and reject the same files.
  Exact,
};

struct MeshFile {
  std::string path;
  std::string format;                        // "OFF", "OBJ", "PLY", "STL", or the extension
  std::vector<Vec3> verts;                   // as stored in the file (no up-axis change)
  std::vector<std::array<uint32_t, 3>> tris;  // indices into verts, file order
  std::vector<uint32_t> tri_material;        // per triangle, index into material_colors
  std::vector<Vec3> material_colors;         // at least one (grey 0.8 by default)
  size_t dropped_degenerate = 0;             // triangles dropped: two corners on one vertex
};

// Reads, checks and imports a mesh file (see above). Throws SceneError (one line).
MeshFile read_mesh_file(const std::string& path, MeshCoordinates coords = MeshCoordinates::Importer);

// Memory limit of the importing child process in MiB above the parent's address space
// (default 2048; environment RU_MESH_MEMORY_MB overrides; > 0 here overrides both, 0 restores).
void set_mesh_memory_limit_mb(double mib);

}  // namespace ru::scene
