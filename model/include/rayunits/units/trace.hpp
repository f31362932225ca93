// rayunits units: binary trace of ray-triangle and ray-box pairs (docs/UNITS.md "Trace format").
//
// File layout, all integers and doubles little endian:
//   header (32 bytes): magic "RUTRACE\0" (8 bytes) | u32 version = 1 | u32 header size = 32 |
//                      u64 number of tri records | u64 number of box records
//   records, in any order, until end of file; each starts with u32 kind | u32 reserved = 0:
//     kind 1 (tri, 144 bytes): 17 float64  a.xyz d.xyz p0.xyz p1.xyz p2.xyz t_min t_max
//     kind 2 (box, 120 bytes): 14 float64  o.xyz inv.xyz lo.xyz hi.xyz t_min t_max
//                              (inv = 1/d per component, +-INF for a zero component)
// The header counts are written when the writer is closed; a reader checks them against the
// records it finds. Malformed files give a TraceError with one line naming the file, the byte
// offset and what was expected.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayunits/units/vec.hpp"

namespace ru::units {

class TraceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TriRecord {
  Vec3d a, d, p0, p1, p2;
  double t_min = 0.0, t_max = INFINITY;
};

struct BoxRecord {
  Vec3d o, inv, lo, hi;
  double t_min = 0.0, t_max = INFINITY;
};

struct Trace {
  std::vector<TriRecord> tris;
  std::vector<BoxRecord> boxes;
};

inline constexpr char kTraceMagic[8] = {'R', 'U', 'T', 'R', 'A', 'C', 'E', '\0'};
inline constexpr uint32_t kTraceVersion = 1;
inline constexpr uint32_t kTraceHeaderBytes = 32;
inline constexpr uint32_t kTraceKindTri = 1, kTraceKindBox = 2;
inline constexpr size_t kTraceTriBytes = 8 + 17 * 8, kTraceBoxBytes = 8 + 14 * 8;

class TraceWriter {
 public:
  // Opens (truncates) path; throws TraceError if it cannot be created.
  explicit TraceWriter(const std::string& path);
  ~TraceWriter();  // closes (errors are swallowed: call close() to see them)
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  void write(const TriRecord& r);
  void write(const BoxRecord& r);
  // Patches the header counts and closes the file; throws TraceError on an I/O error.
  void close();

  uint64_t tri_count() const { return ntri_; }
  uint64_t box_count() const { return nbox_; }

 private:
  void put(const void* p, size_t n);
  std::string path_;
  std::FILE* f_ = nullptr;
  uint64_t ntri_ = 0, nbox_ = 0;
};

// Reads a whole trace; throws TraceError with one line on any malformation.
Trace read_trace(const std::string& path);
void write_trace(const std::string& path, const Trace& t);

}  // namespace ru::units
