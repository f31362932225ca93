// The one mesh-file loader (scene/mesh_file.hpp): parent-side checks and readers for OFF, OBJ,
// PLY and STL, the Assimp import in a sandboxed child (time and memory limits), the indexed
// mesh; the Scene built from it (load_mesh); locating the CGAL demo meshes.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <string_view>
#include <unordered_map>

#include "rayunits/scene/mesh_file.hpp"
#include "rayunits/scene/scene.hpp"

namespace ru::scene {
namespace {

// Error text from files or the importer may hold any byte: one printable line.
std::string one_line(std::string s) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  if (s.size() > 400) s = s.substr(0, 400) + "...";
  return s.empty() ? std::string("unknown error") : s;
}

// A token of the file, quoted for an error message (bounded, printable).
std::string quote(std::string_view t) {
  std::string s(t.substr(0, 40));
  if (t.size() > 40) s += "...";
  return "'" + one_line(s) + "'";
}

bool file_exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string lower_ext(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot + 1);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// Frames the bounding box (z up): the eye looks from the front-right-above so that the model
// nearly fills a square image, as in Mirth's bunny view.
void frame_camera(Scene& s) {
  Vec3 lo = s.bounds_lo(), hi = s.bounds_hi();
  Vec3 c = (lo + hi) * 0.5;
  double r = 0.5 * length(hi - lo);
  s.camera.fov_deg = 35.0;
  double dist = r / std::tan(0.5 * s.camera.fov_deg * 3.14159265358979323846 / 180.0) * 0.85;
  Vec3 dir = normalize(Vec3{0.35, -1.0, 0.35});
  s.camera.eye = c + dir * dist;
  s.camera.look_at = c;
  s.camera.up = {0, 0, 1};
  s.light = c + Vec3{1.2, -2.0, 2.5} * r;
  s.unit = r;  // epsilon and texture frequency relative to the model's size
}

double g_timeout_override = 0;
double g_memory_override_mb = 0;

double memory_limit_mb() {
  if (g_memory_override_mb > 0) return g_memory_override_mb;
  if (const char* e = std::getenv("RU_MESH_MEMORY_MB")) {
    const double v = std::atof(e);
    if (v > 0) return v;
  }
  return 2048;
}

// ------------------------------------------------------------------------------------------
// Parent-side readers. Constant memory per line (lines longer than 1 MiB are an error); what
// they keep is bounded by counts that were checked against the file size.

constexpr size_t kMaxLine = 1 << 20;

class LineReader {
 public:
  LineReader(const std::string& path, const std::string& what) : what_(what) {
    f_ = std::fopen(path.c_str(), "rb");
    if (!f_) throw SceneError("cannot open mesh file '" + path + "': not readable");
  }
  ~LineReader() {
    if (f_) std::fclose(f_);
  }
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  // Next line without its end-of-line; false at the end of the file.
  bool next(std::string_view* line) {
    for (;;) {
      const size_t nl = buf_.find('\n', pos_);
      if (nl != std::string::npos) {
        *line = std::string_view(buf_).substr(pos_, nl - pos_);
        pos_ = nl + 1;
        ++lineno_;
        return true;
      }
      if (buf_.size() - pos_ > kMaxLine)
        throw SceneError(what_ + ":" + std::to_string(lineno_ + 1) + ": line longer than 1 MiB");
      buf_.erase(0, pos_);
      pos_ = 0;
      char chunk[65536];
      const size_t n = std::fread(chunk, 1, sizeof chunk, f_);
      if (n == 0) {
        if (buf_.empty()) return false;
        last_.swap(buf_);  // the last line has no end-of-line
        buf_.clear();
        *line = last_;
        ++lineno_;
        return true;
      }
      buf_.append(chunk, n);
    }
  }
  long lineno() const { return lineno_; }
  std::string where() const { return what_ + ":" + std::to_string(lineno_); }

 private:
  std::FILE* f_ = nullptr;
  std::string what_, buf_, last_;
  size_t pos_ = 0;
  long lineno_ = 0;
};

void tokenize(std::string_view line, std::vector<std::string_view>* out) {
  out->clear();
  size_t i = 0;
  auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\0'; };
  while (i < line.size()) {
    while (i < line.size() && space(line[i])) ++i;
    size_t j = i;
    while (j < line.size() && !space(line[j])) ++j;
    if (j > i) out->push_back(line.substr(i, j - i));
    i = j;
  }
}

// Comments: '#' to the end of the line (OFF and OBJ).
std::string_view strip_comment(std::string_view line) {
  const size_t h = line.find('#');
  return h == std::string_view::npos ? line : line.substr(0, h);
}

// A coordinate is the number at the start of its token, as Assimp and the watertightness
// study's earlier reader (istream >> double) read it: "3.1+e2" (Assimp's own test model
// OBJ/number_formats.obj) is 3.1. A token that does not start with a number is an error.
bool parse_double(std::string_view t, double* v) {
  if (t.empty()) return false;
  char buf[256];
  const size_t n = std::min<size_t>(t.size(), sizeof buf - 1);
  std::memcpy(buf, t.data(), n);
  buf[n] = '\0';
  char* end = nullptr;
  *v = std::strtod(buf, &end);
  return end != buf;
}

bool parse_long(std::string_view t, long long* v) {
  if (t.empty() || t.size() > 30) return false;
  char buf[32];
  std::memcpy(buf, t.data(), t.size());
  buf[t.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  *v = std::strtoll(buf, &end, 10);
  return end == buf + t.size() && errno == 0;
}

bool parse_count(std::string_view t, uint64_t* v) {
  if (t.empty() || t.size() > 20 || t.find_first_not_of("0123456789") != std::string_view::npos) return false;
  errno = 0;
  *v = std::strtoull(std::string(t).c_str(), nullptr, 10);
  return errno == 0;
}

const char* kCoordRule = "accepted: finite numbers of magnitude at most 2^64";

void check_coordinate(double v, std::string_view tok, const std::string& where, const std::string& what) {
  if (!std::isfinite(v))
    throw SceneError(where + ": " + what + " has the non-finite coordinate " + quote(tok) + " (" + kCoordRule + ")");
  if (std::fabs(v) > kMaxMeshCoordinate)
    throw SceneError(where + ": " + what + " has the huge coordinate " + quote(tok) + " (" + kCoordRule + ")");
}

struct TextMesh {
  std::vector<Vec3> verts;
  std::vector<std::array<uint32_t, 3>> tris;
  size_t faces = 0;
};

void fan(TextMesh* m, const std::vector<uint32_t>& poly) {
  for (size_t i = 1; i + 1 < poly.size(); ++i) m->tris.push_back({poly[0], poly[i], poly[i + 1]});
}

// OFF (Assimp's dialect: one vertex or face per line, '#' comments; header [ST][C][N][4][n]OFF,
// or none, then "nv nf [ne]" on the same or the next line).
TextMesh read_off(const std::string& path, uint64_t file_size, bool keep) {
  const std::string what = "mesh file " + path;
  LineReader r(path, what);
  std::vector<std::string_view> tok;
  std::string_view line;
  auto next_significant = [&]() {
    while (r.next(&line)) {
      tokenize(strip_comment(line), &tok);
      if (!tok.empty()) return true;
    }
    return false;
  };
  const char* header_rule = "accepted: an OFF header (OFF, COFF, NOFF, STOFF, 4OFF, nOFF, ...) and the vertex, face "
                            "and edge counts";
  if (!next_significant()) throw SceneError(what + ": empty file (" + header_rule + ")");
  size_t ti = 0;
  bool homogeneous = false, dimension = false;
  int dims = 3;
  {
    std::string_view k = tok[0];
    if (k.size() >= 3 && k.substr(k.size() - 3) == "OFF") {
      std::string_view p = k.substr(0, k.size() - 3);
      if (p.substr(0, 2) == "ST") p.remove_prefix(2);
      if (!p.empty() && p[0] == 'C') p.remove_prefix(1);
      if (!p.empty() && p[0] == 'N') p.remove_prefix(1);
      if (!p.empty() && p[0] == '4') homogeneous = true, p.remove_prefix(1);
      if (!p.empty() && p[0] == 'n') dimension = true, p.remove_prefix(1);
      if (!p.empty()) throw SceneError(r.where() + ": unknown OFF header " + quote(k) + " (" + header_rule + ")");
      ti = 1;
      if (tok.size() > 1 && tok[1] == "BINARY")
        throw SceneError(r.where() + ": binary OFF is not supported (accepted: ASCII OFF)");
    } else if (k[0] < '0' || k[0] > '9') {
      throw SceneError(r.where() + ": expected an OFF header, found " + quote(k) + " (" + header_rule + ")");
    }
  }
  auto next_token = [&](std::string_view* t) {
    if (ti >= tok.size()) {
      if (!next_significant()) return false;
      ti = 0;
    }
    *t = tok[ti++];
    return true;
  };
  std::string_view t;
  if (dimension) {
    uint64_t d = 0;
    if (!next_token(&t) || !parse_count(t, &d) || d < 1 || d > 3)
      throw SceneError(r.where() + ": nOFF needs a dimension of 1, 2 or 3");
    dims = static_cast<int>(d);
  }
  uint64_t nv = 0, nf = 0;
  if (!next_token(&t) || !parse_count(t, &nv) || !next_token(&t) || !parse_count(t, &nf))
    throw SceneError(r.where() + ": expected the vertex and face counts (" + header_rule + ")");
  if (ti < tok.size()) ++ti;  // the edge count (unused)
  if (nv == 0 || nf == 0)
    throw SceneError(r.where() + ": the OFF header claims " + std::to_string(nv) + " vertices and " +
                     std::to_string(nf) + " faces (accepted: at least 1 of each)");
  // Counts against the file size before anything is allocated: a vertex line holds at least
  // one character and one separator per coordinate, a face line "3 a b c" and an end-of-line.
  const int per_vertex = dims + (homogeneous ? 1 : 0);
  const uint64_t vbytes = 2 * static_cast<uint64_t>(per_vertex), fbytes = 8;
  if (nv > 0xffffffffull || nf > 0xffffffffull || nv * vbytes + nf * fbytes > file_size + 1)
    throw SceneError(r.where() + ": the OFF header claims " + std::to_string(nv) + " vertices and " +
                     std::to_string(nf) + " faces, more than a file of " + std::to_string(file_size) +
                     " bytes can hold (each vertex takes at least " + std::to_string(vbytes) +
                     " bytes, each face 8)");
  TextMesh m;
  if (keep) m.verts.reserve(static_cast<size_t>(nv));
  if (ti < tok.size())
    throw SceneError(r.where() + ": unexpected " + quote(tok[ti]) + " after the counts (" + header_rule + ")");
  for (uint64_t i = 0; i < nv; ++i) {
    if (!next_significant())
      throw SceneError(r.where() + ": the file ends after " + std::to_string(i) + " of the " + std::to_string(nv) +
                       " vertices its header claims");
    const std::string vname = "vertex " + std::to_string(i);
    double c[4] = {0, 0, 0, 1};
    if (tok.size() < static_cast<size_t>(per_vertex))
      throw SceneError(r.where() + ": " + vname + ": expected " + std::to_string(per_vertex) + " coordinates, found " +
                       std::to_string(tok.size()) + " numbers");
    for (int k = 0; k < per_vertex; ++k) {
      if (!parse_double(tok[k], &c[k]))
        throw SceneError(r.where() + ": " + vname + ": " + quote(tok[k]) + " is not a number (expected 'x y z')");
      check_coordinate(c[k], tok[k], r.where(), vname);
    }
    if (homogeneous) {
      const double w = c[dims];
      if (w == 0) throw SceneError(r.where() + ": " + vname + ": homogeneous coordinate 0 (accepted: w != 0)");
      for (int k = 0; k < dims; ++k) c[k] /= w;
      for (int k = 0; k < dims; ++k)
        check_coordinate(c[k], tok[k], r.where(), vname + " (divided by w)");
      c[dims] = 0;
    }
    if (keep) m.verts.push_back({c[0], c[1], c[2]});
  }
  std::vector<uint32_t> poly;
  for (uint64_t i = 0; i < nf; ++i) {
    if (!next_significant())
      throw SceneError(r.where() + ": the file ends after " + std::to_string(i) + " of the " + std::to_string(nf) +
                       " faces its header claims");
    const std::string fname = "face " + std::to_string(i);
    uint64_t n = 0;
    if (!parse_count(tok[0], &n) || n < 3)
      throw SceneError(r.where() + ": " + fname + ": expected 'n i0 i1 ... ' with n >= 3 vertices, found " + quote(tok[0]));
    if (tok.size() < n + 1)
      throw SceneError(r.where() + ": " + fname + ": " + std::to_string(n) + " vertex indices announced, " +
                       std::to_string(tok.size() - 1) + " given");
    poly.clear();
    for (uint64_t k = 0; k < n; ++k) {
      uint64_t idx = 0;
      if (!parse_count(tok[k + 1], &idx))
        throw SceneError(r.where() + ": " + fname + ": bad vertex index " + quote(tok[k + 1]) +
                         " (accepted: 0.." + std::to_string(nv - 1) + ")");
      if (idx >= nv)
        throw SceneError(r.where() + ": " + fname + ": vertex index " + std::to_string(idx) + " out of range (the file has " +
                         std::to_string(nv) + " vertices: 0.." + std::to_string(nv - 1) + ")");
      poly.push_back(static_cast<uint32_t>(idx));
    }
    ++m.faces;
    if (keep) fan(&m, poly);
  }
  return m;
}

// OBJ: "v x y z ...", "vt", "vn", "f v[/t][/n] ..." (1-based or negative), "l", "p"; everything
// else (groups, materials, smoothing) is left to the importer.
TextMesh read_obj(const std::string& path, bool keep) {
  const std::string what = "mesh file " + path;
  LineReader r(path, what);
  std::vector<std::string_view> tok;
  std::string_view line;
  TextMesh m;
  uint64_t nv = 0, nt = 0, nn = 0;
  std::vector<uint32_t> poly;
  auto index = [&](std::string_view t, uint64_t count, const char* kind, const char* kinds, bool required) -> uint64_t {
    if (t.empty()) {
      if (required) throw SceneError(r.where() + ": empty vertex index in a face");
      return 0;
    }
    long long v = 0;
    if (!parse_long(t, &v) || v == 0)
      throw SceneError(r.where() + ": bad " + kind + " index " + quote(t) + " (accepted: 1..N, or -N..-1 counting back)");
    const long long n = static_cast<long long>(count);
    const long long idx = v > 0 ? v - 1 : n + v;
    if (idx < 0 || idx >= n)
      throw SceneError(r.where() + ": " + kind + " index " + std::to_string(v) + " out of range (" + std::to_string(count) +
                       " " + (count == 1 ? kind : kinds) + " before this line: 1.." + std::to_string(count) + " or -" +
                       std::to_string(count) + "..-1)");
    return static_cast<uint64_t>(idx);
  };
  while (r.next(&line)) {
    tokenize(strip_comment(line), &tok);
    if (tok.empty()) continue;
    const std::string_view tag = tok[0];
    if (tag == "v") {
      double c[3];
      if (tok.size() < 4) throw SceneError(r.where() + ": expected 'v x y z'");
      for (int k = 0; k < 3; ++k) {
        if (!parse_double(tok[k + 1], &c[k]))
          throw SceneError(r.where() + ": " + quote(tok[k + 1]) + " is not a number (expected 'v x y z')");
        check_coordinate(c[k], tok[k + 1], r.where(), "vertex " + std::to_string(nv + 1));
      }
      if (nv >= 0xffffffffull) throw SceneError(r.where() + ": more than 2^32 - 1 vertices");
      ++nv;
      if (keep) m.verts.push_back({c[0], c[1], c[2]});
    } else if (tag == "vt") {
      ++nt;
    } else if (tag == "vn") {
      ++nn;
    } else if (tag == "f" || tag == "l" || tag == "p") {
      poly.clear();
      for (size_t k = 1; k < tok.size(); ++k) {
        const std::string_view t = tok[k];
        const size_t s1 = t.find('/');
        const std::string_view vpart = t.substr(0, s1);
        poly.push_back(static_cast<uint32_t>(index(vpart, nv, "vertex", "vertices", true)));
        if (s1 != std::string_view::npos) {
          std::string_view rest = t.substr(s1 + 1);
          const size_t s2 = rest.find('/');
          index(rest.substr(0, s2), nt, "texture coordinate", "texture coordinates", false);
          if (s2 != std::string_view::npos) index(rest.substr(s2 + 1), nn, "normal", "normals", false);
        }
      }
      if (tag == "f") {
        if (poly.size() < 3)
          throw SceneError(r.where() + ": a face needs at least 3 vertices, found " + std::to_string(poly.size()) +
                           " (points and lines are 'p' and 'l')");
        ++m.faces;
        if (keep) fan(&m, poly);
      }
    }
  }
  if (m.faces == 0) throw SceneError(what + ": no faces (accepted: 'f' lines with 3 or more vertex indices)");
  return m;
}

// PLY: the header must end, and the element counts must fit the bytes after it.
void check_ply(const std::string& path, const std::string& head, uint64_t file_size) {
  const std::string what = "malformed PLY file '" + path + "'";
  size_t end = head.find("end_header");
  if (end == std::string::npos) throw SceneError(what + ": header without end_header");
  size_t body = head.find('\n', end);
  body = body == std::string::npos ? head.size() : body + 1;
  std::vector<std::string_view> tok;
  std::string_view h = std::string_view(head).substr(0, end);
  bool ascii = true;
  struct Prop {
    std::string name;
    bool list = false, integer = false;
  };
  struct Elem {
    std::string name;
    uint64_t count = 0, min_bytes = 0;
    std::vector<Prop> props;
  };
  std::vector<Elem> elems;
  auto is_int = [](std::string_view t) { return !(t == "float" || t == "float32" || t == "double" || t == "float64"); };
  auto type_size = [&](std::string_view t) -> uint64_t {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    throw SceneError(what + ": unknown property type " + quote(t) +
                     " (accepted: char uchar short ushort int uint float double, int8 ... float64)");
  };
  size_t pos = 0;
  while (pos < h.size()) {
    size_t nl = h.find('\n', pos);
    if (nl == std::string_view::npos) nl = h.size();
    tokenize(h.substr(pos, nl - pos), &tok);
    pos = nl + 1;
    if (tok.empty()) continue;
    if (tok[0] == "format" && tok.size() >= 2) {
      if (tok[1] == "ascii") ascii = true;
      else if (tok[1] == "binary_little_endian" || tok[1] == "binary_big_endian") ascii = false;
      else
        throw SceneError(what + ": unknown format " + quote(tok[1]) +
                         " (accepted: ascii, binary_little_endian, binary_big_endian)");
    } else if (tok[0] == "element") {
      Elem e;
      if (tok.size() < 3 || !parse_count(tok[2], &e.count) || e.count > 0xffffffffull)
        throw SceneError(what + ": expected 'element NAME COUNT' with COUNT in 0..4294967295");
      e.name = std::string(tok[1]);
      elems.push_back(e);
    } else if (tok[0] == "property") {
      if (elems.empty()) throw SceneError(what + ": property before any element");
      if (tok.size() >= 5 && tok[1] == "list") {
        const uint64_t cs = type_size(tok[2]);
        type_size(tok[3]);
        elems.back().min_bytes += ascii ? 2 : cs;  // a list may be empty: its count only
        elems.back().props.push_back({std::string(tok[4]), true, is_int(tok[3])});
      } else if (tok.size() >= 3) {
        const uint64_t s = type_size(tok[1]);
        elems.back().min_bytes += ascii ? 2 : s;
        elems.back().props.push_back({std::string(tok[2]), false, is_int(tok[1])});
      } else {
        throw SceneError(what + ": expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
      }
    }
  }
  const uint64_t avail = file_size > body ? file_size - body : 0;
  long double need = 0;
  for (const auto& e : elems) need += static_cast<long double>(e.count) * static_cast<long double>(e.min_bytes);
  if (need > static_cast<long double>(avail) + 1) {
    std::string claims;
    for (const auto& e : elems)
      claims += (claims.empty() ? "" : ", ") + std::to_string(e.count) + " " + one_line(e.name.substr(0, 40));
    throw SceneError(what + ": the header claims " + claims + " elements, more than the " + std::to_string(avail) +
                     " bytes after the header can hold");
  }
  if (!ascii) return;  // binary: the importer's validation checks the indices, finish() the coordinates
  // ASCII body: every number parses, coordinates are finite and not huge, faces have >= 3
  // vertex indices in range, and the file holds every element its header claims.
  uint64_t nv = 0;
  for (const auto& e : elems)
    if (e.name == "vertex") nv = e.count;
  const std::string where = "mesh file " + path;
  LineReader r(path, where);
  std::string_view line;
  while (r.next(&line)) {
    tokenize(line, &tok);
    if (!tok.empty() && tok[0] == "end_header") break;
  }
  size_t ti = 0;
  tok.clear();
  auto next_token = [&](std::string_view* t) {
    while (ti >= tok.size()) {
      if (!r.next(&line)) return false;
      tokenize(line, &tok);
      ti = 0;
    }
    *t = tok[ti++];
    return true;
  };
  std::string_view t;
  for (const auto& e : elems) {
    const bool vertex = e.name == "vertex", face = e.name == "face";
    for (uint64_t i = 0; i < e.count; ++i) {
      const std::string ename = one_line(e.name.substr(0, 40)) + " " + std::to_string(i);
      auto need = [&](const Prop& p) {
        if (!next_token(&t))
          throw SceneError(r.where() + ": the file ends in " + ename + " (the header claims " + std::to_string(e.count) +
                           " " + one_line(e.name.substr(0, 40)) + " elements; property " + one_line(p.name.substr(0, 40)) +
                           " is missing)");
      };
      for (const auto& p : e.props) {
        const bool indices = face && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
        uint64_t n = 1;
        if (p.list) {
          need(p);
          if (!parse_count(t, &n))
            throw SceneError(r.where() + ": " + ename + ": bad list length " + quote(t));
          if (indices && n < 3)
            throw SceneError(r.where() + ": " + ename + ": a face needs at least 3 vertices, found " + std::to_string(n));
        }
        for (uint64_t k = 0; k < n; ++k) {
          need(p);
          if (p.integer) {
            long long v = 0;
            if (!parse_long(t, &v))
              throw SceneError(r.where() + ": " + ename + ": " + quote(t) + " is not an integer (property " +
                               one_line(p.name.substr(0, 40)) + ")");
            if (indices && (v < 0 || static_cast<uint64_t>(v) >= nv))
              throw SceneError(r.where() + ": " + ename + ": vertex index " + std::to_string(v) + " out of range (the file has " +
                               std::to_string(nv) + " vertices: 0.." + std::to_string(nv ? nv - 1 : 0) + ")");
          } else {
            double v = 0;
            if (!parse_double(t, &v))
              throw SceneError(r.where() + ": " + ename + ": " + quote(t) + " is not a number (property " +
                               one_line(p.name.substr(0, 40)) + ")");
            if (vertex && (p.name == "x" || p.name == "y" || p.name == "z")) check_coordinate(v, t, r.where(), ename);
          }
        }
      }
    }
  }
}

// STL: ASCII ("solid ...") or binary (80-byte header, uint32 count, 50 bytes per triangle).
void check_stl(const std::string& path, const std::string& head, uint64_t file_size) {
  const std::string what = "malformed STL file '" + path + "'";
  if (file_size >= 84 && head.size() >= 84) {
    uint32_t n = 0;
    std::memcpy(&n, head.data() + 80, 4);
    if (84 + 50 * static_cast<uint64_t>(n) == file_size) {
      if (n == 0) throw SceneError(what + ": binary STL with 0 triangles");
      return;
    }
  }
  const size_t p = head.find_first_not_of(" \t\r\n");
  if (p != std::string::npos && head.compare(p, 5, "solid") == 0) return;
  std::string claim;
  if (file_size >= 84 && head.size() >= 84) {
    uint32_t n = 0;
    std::memcpy(&n, head.data() + 80, 4);
    claim = ": as binary STL it claims " + std::to_string(n) + " triangles (" +
            std::to_string(84 + 50 * static_cast<uint64_t>(n)) + " bytes), the file has " + std::to_string(file_size);
  } else {
    claim = ": " + std::to_string(file_size) + " bytes";
  }
  throw SceneError(what + claim + " (accepted: ASCII STL starting with 'solid', or binary STL of exactly 84 + 50 N bytes)");
}

// ------------------------------------------------------------------------------------------
// The Assimp import proper (runs in the sandbox child): a triangle soup with materials.
struct Soup {
  std::vector<Vec3> colors;
  std::vector<std::array<Vec3, 3>> tris;
  std::vector<uint32_t> material;
};

Soup import_in_process(const std::string& path) {
  Assimp::Importer imp;
  // Points and lines are dropped; polygons are triangulated; node transforms are applied.
  imp.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* as = nullptr;
  try {
    as = imp.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_PreTransformVertices |
                                aiProcess_ValidateDataStructure);
  } catch (const std::exception& e) {  // Assimp normally reports through GetErrorString
    throw SceneError("cannot load mesh '" + path + "': " + one_line(e.what()));
  }
  if (!as) throw SceneError("cannot load mesh '" + path + "': " + one_line(imp.GetErrorString()));
  if ((as->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !as->mRootNode)
    throw SceneError("cannot load mesh '" + path + "': incomplete scene");
  Soup s;
  for (unsigned i = 0; i < as->mNumMaterials; ++i) {
    Vec3 col{0.8, 0.8, 0.8};
    aiColor4D c;
    if (as->mMaterials[i] && as->mMaterials[i]->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS &&
        std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && (c.r + c.g + c.b) > 0.05)
      col = {std::min(1.0, std::max(0.0, double(c.r))), std::min(1.0, std::max(0.0, double(c.g))),
             std::min(1.0, std::max(0.0, double(c.b)))};
    s.colors.push_back(col);
  }
  if (s.colors.empty()) s.colors.push_back({0.8, 0.8, 0.8});
  for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
    const aiMesh* m = as->mMeshes[mi];
    if (!m || !(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !m->mVertices) continue;
    uint32_t mat = m->mMaterialIndex < s.colors.size() ? m->mMaterialIndex : 0;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3 || !face.mIndices) continue;
      std::array<Vec3, 3> t;
      for (int k = 0; k < 3; ++k) {
        unsigned vi = face.mIndices[k];
        if (vi >= m->mNumVertices) throw SceneError("malformed mesh '" + path + "': vertex index out of range");
        const aiVector3D& v = m->mVertices[vi];
        t[k] = Vec3{v.x, v.y, v.z};
      }
      s.tris.push_back(t);
      s.material.push_back(mat);
    }
  }
  if (s.tris.empty()) throw SceneError("mesh '" + path + "' contains no triangles");
  return s;
}

// --- sandbox: Assimp runs in a forked child that sends the triangles back through a pipe, so
// that a hang (Assimp 5.2.5 loops forever on a PLY header cut short), a crash or a runaway
// allocation inside the importer becomes one error line instead of taking the program (or the
// machine) down. The child's address space is limited (RLIMIT_AS) to the parent's plus the
// memory limit; its stdout/stderr go to /dev/null (the error stays one line).
struct Buf {
  std::string data;
  template <class V>
  void put(const V& v) {
    data.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
};

bool write_all(int fd, const std::string& d) {
  size_t off = 0;
  while (off < d.size()) {
    ssize_t n = ::write(fd, d.data() + off, d.size() - off);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    off += static_cast<size_t>(n);
  }
  return true;
}

std::string encode(const Soup& s) {
  Buf b;
  b.put(uint32_t{0});
  b.put(static_cast<uint64_t>(s.colors.size()));
  for (const auto& c : s.colors) b.put(c);
  b.put(static_cast<uint64_t>(s.tris.size()));
  for (size_t i = 0; i < s.tris.size(); ++i) {
    for (const auto& p : s.tris[i]) b.put(p);
    b.put(s.material[i]);
  }
  return b.data;
}

struct Reader {
  const std::string& d;
  size_t off = 0;
  template <class V>
  bool get(V* v) {
    if (off + sizeof(V) > d.size()) return false;
    std::memcpy(v, d.data() + off, sizeof(V));
    off += sizeof(V);
    return true;
  }
};

constexpr int kExitOutOfMemory = 4;

[[noreturn]] void child_out_of_memory() { ::_exit(kExitOutOfMemory); }

uint64_t address_space_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  unsigned long long pages = 0;
  if (f) {
    if (std::fscanf(f, "%llu", &pages) != 1) pages = 0;
    std::fclose(f);
  }
  return pages * static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
}

Soup run_sandboxed(const std::string& path, double timeout_s) {
  const double limit_mb = memory_limit_mb();
  const uint64_t limit_bytes = static_cast<uint64_t>(limit_mb * 1048576.0);
  const std::string limit_text = std::to_string(static_cast<long long>(limit_mb)) + " MiB";
  int fds[2];
  if (::pipe(fds) != 0) throw SceneError("cannot load mesh '" + path + "': no pipe for the importer process");
  std::fflush(nullptr);
  pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw SceneError("cannot load mesh '" + path + "': cannot start the importer process");
  }
  if (pid == 0) {  // child: limit, import, send, _exit (no destructors, no atexit handlers)
    ::close(fds[0]);
    const int devnull = ::open("/dev/null", O_RDWR);
    if (devnull >= 0) {
      ::dup2(devnull, 1);
      ::dup2(devnull, 2);
    }
    rlimit rl;
    if (::getrlimit(RLIMIT_AS, &rl) == 0) {
      const rlim_t want = static_cast<rlim_t>(address_space_bytes() + limit_bytes);
      if (rl.rlim_cur == RLIM_INFINITY || rl.rlim_cur > want) rl.rlim_cur = want;
      ::setrlimit(RLIMIT_AS, &rl);
    }
    std::set_new_handler(child_out_of_memory);
    std::string out;
    try {
      out = encode(import_in_process(path));
    } catch (const std::bad_alloc&) {
      ::_exit(kExitOutOfMemory);
    } catch (const std::exception& e) {
      std::string m = e.what();
      if (m.find("bad_alloc") != std::string::npos) ::_exit(kExitOutOfMemory);  // caught inside Assimp
      Buf b;
      b.put(uint32_t{1});
      b.put(static_cast<uint64_t>(m.size()));
      b.data += m;
      out = b.data;
    }
    bool ok = write_all(fds[1], out);
    ::close(fds[1]);
    ::_exit(ok ? 0 : 3);
  }
  ::close(fds[1]);
  std::string data;
  bool timed_out = false, too_big = false;
  auto t0 = std::chrono::steady_clock::now();
  char chunk[65536];
  for (;;) {
    double left = timeout_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (left <= 0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    int r = ::poll(&p, 1, static_cast<int>(std::min(left * 1000.0, 1000.0)) + 1);
    if (r < 0 && errno == EINTR) continue;
    if (r == 0) continue;
    ssize_t n = ::read(fds[0], chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // EOF (or error): the child is done
    data.append(chunk, static_cast<size_t>(n));
    if (data.size() > limit_bytes) {
      too_big = true;
      break;
    }
  }
  ::close(fds[0]);
  if (timed_out || too_big) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    throw SceneError("cannot load mesh '" + path + "': the importer did not finish within " +
                     std::to_string(static_cast<int>(timeout_s)) + " s (malformed file? RU_MESH_TIMEOUT raises the limit)");
  if (too_big || (WIFEXITED(status) && WEXITSTATUS(status) == kExitOutOfMemory))
    throw SceneError("cannot load mesh '" + path + "': the import needs more than its memory limit of " + limit_text +
                     " (malformed file? RU_MESH_MEMORY_MB raises the limit)");
  if (WIFSIGNALED(status))
    throw SceneError("cannot load mesh '" + path + "': the importer crashed (signal " +
                     std::to_string(WTERMSIG(status)) + "; malformed file?)");
  Reader rd{data};
  uint32_t tag = 9;
  if (!rd.get(&tag)) throw SceneError("cannot load mesh '" + path + "': the importer sent nothing");
  if (tag == 1) {
    uint64_t len = 0;
    rd.get(&len);
    throw SceneError(one_line(data.substr(rd.off, static_cast<size_t>(std::min<uint64_t>(len, data.size())))));
  }
  Soup s;
  uint64_t nm = 0, nt = 0;
  const size_t tri_bytes = 3 * sizeof(Vec3) + sizeof(uint32_t);
  bool ok = tag == 0 && rd.get(&nm) && nm >= 1 && nm <= data.size() / sizeof(Vec3);
  for (uint64_t i = 0; ok && i < nm; ++i) {
    Vec3 c;
    ok = rd.get(&c);
    s.colors.push_back(c);
  }
  ok = ok && rd.get(&nt) && nt <= (data.size() - rd.off) / tri_bytes;  // counts against the reply size
  if (ok) {
    s.tris.reserve(static_cast<size_t>(nt));
    s.material.reserve(static_cast<size_t>(nt));
  }
  for (uint64_t i = 0; ok && i < nt; ++i) {
    std::array<Vec3, 3> t;
    uint32_t mat = 0;
    ok = rd.get(&t[0]) && rd.get(&t[1]) && rd.get(&t[2]) && rd.get(&mat) && mat < nm;
    s.tris.push_back(t);
    s.material.push_back(mat);
  }
  if (!ok || rd.off != data.size()) throw SceneError("cannot load mesh '" + path + "': truncated importer reply");
  return s;
}

// Corners at bit-identical positions become one vertex (file order of first appearance).
struct PosKey {
  uint64_t b[3];
  bool operator==(const PosKey& o) const { return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2]; }
};
struct PosHash {
  size_t operator()(const PosKey& k) const {
    uint64_t h = k.b[0] * 0x9e3779b97f4a7c15ull;
    h ^= k.b[1] + 0x7f4a7c159e3779b9ull + (h << 6) + (h >> 2);
    h ^= k.b[2] + 0x94d049bb133111ebull + (h << 6) + (h >> 2);
    return static_cast<size_t>(h);
  }
};

void join(const Soup& s, MeshFile* m) {
  std::unordered_map<PosKey, uint32_t, PosHash> index;
  index.reserve(s.tris.size() * 2);
  m->tris.reserve(s.tris.size());
  m->tri_material.reserve(s.tris.size());
  for (size_t i = 0; i < s.tris.size(); ++i) {
    std::array<uint32_t, 3> t;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = s.tris[i][k];
      PosKey key;
      std::memcpy(&key.b[0], &p.x, 8);
      std::memcpy(&key.b[1], &p.y, 8);
      std::memcpy(&key.b[2], &p.z, 8);
      auto [it, fresh] = index.emplace(key, static_cast<uint32_t>(m->verts.size()));
      if (fresh) m->verts.push_back(p);
      t[k] = it->second;
    }
    m->tris.push_back(t);
    m->tri_material.push_back(s.material[i]);
  }
  m->material_colors = s.colors;
}

std::string coord_text(const Vec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "(%g %g %g)", v.x, v.y, v.z);
  return b;
}

// Checks every vertex and drops the triangles with two corners on one vertex.
void finish(MeshFile* m) {
  for (const auto& v : m->verts)
    for (double c : {v.x, v.y, v.z})
      if (!std::isfinite(c) || std::fabs(c) > kMaxMeshCoordinate)
        throw SceneError("mesh file " + m->path + ": a vertex " + coord_text(v) + " has a " +
                         (std::isfinite(c) ? "huge" : "non-finite") + " coordinate (" + kCoordRule + ")");
  size_t w = 0;
  for (size_t i = 0; i < m->tris.size(); ++i) {
    const auto& t = m->tris[i];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    m->tris[w] = t;
    m->tri_material[w] = m->tri_material[i];
    ++w;
  }
  m->dropped_degenerate = m->tris.size() - w;
  const size_t total = m->tris.size();
  m->tris.resize(w);
  m->tri_material.resize(w);
  if (m->tris.empty())
    throw SceneError("mesh file " + m->path + ": no triangles" +
                     (total ? " (all " + std::to_string(total) + " have two corners on one vertex)" : std::string()));
  if (m->dropped_degenerate)
    std::fprintf(stderr, "rayunits: warning: mesh file %s: dropped %zu of %zu triangles with two corners on one vertex "
                         "(zero area, not part of the surface)\n",
                 m->path.c_str(), m->dropped_degenerate, total);
}

}  // namespace

void set_mesh_load_timeout(double seconds) { g_timeout_override = seconds; }
void set_mesh_memory_limit_mb(double mib) { g_memory_override_mb = mib; }

MeshFile read_mesh_file(const std::string& path, MeshCoordinates coords) {
  if (!file_exists(path)) throw SceneError("cannot open mesh file '" + path + "': no such file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw SceneError("cannot open mesh file '" + path + "': not readable");
  std::string head(65536, '\0');
  probe.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(probe.gcount()));
  probe.close();
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw SceneError("cannot open mesh file '" + path + "': no such file");
  const uint64_t size = static_cast<uint64_t>(st.st_size);

  MeshFile m;
  m.path = path;
  const std::string ext = lower_ext(path);
  m.format = ext == "off" ? "OFF" : ext == "obj" ? "OBJ" : ext == "ply" ? "PLY" : ext == "stl" ? "STL" : ext;
  const bool exact = coords == MeshCoordinates::Exact && (ext == "off" || ext == "obj");
  TextMesh text;
  if (ext == "off") text = read_off(path, size, exact);
  else if (ext == "obj") text = read_obj(path, exact);
  else if (ext == "stl") check_stl(path, head, size);
  // PLY headers must end (Assimp 5.2.5 never returns on a header cut short), whatever the name.
  if (ext == "ply" || head.compare(0, 3, "ply") == 0) check_ply(path, head, size);

  // The importer runs in both modes, so that every command accepts and rejects the same files.
  double timeout = g_timeout_override > 0 ? g_timeout_override : 30.0 + 2.0 * static_cast<double>(size) / 1e6;
  if (const char* e = std::getenv("RU_MESH_TIMEOUT")) timeout = std::max(0.1, std::atof(e));
  Soup soup = run_sandboxed(path, timeout);
  if (exact) {
    m.verts = std::move(text.verts);
    m.tris = std::move(text.tris);
    m.tri_material.assign(m.tris.size(), 0);
    m.material_colors = {{0.8, 0.8, 0.8}};
  } else {
    join(soup, &m);
  }
  finish(&m);
  return m;
}

Scene load_mesh(const std::string& path, char up_axis) {
  if (up_axis != 'y' && up_axis != 'z') throw SceneError("up axis must be 'y' or 'z'");
  const MeshFile f = read_mesh_file(path, MeshCoordinates::Importer);
  Scene s;
  s.name = path;
  for (size_t i = 0; i < f.material_colors.size(); ++i) {
    Material mat;
    mat.name = "mesh" + std::to_string(i);
    mat.color = f.material_colors[i];
    s.materials.push_back(mat);
  }
  s.tris.reserve(f.tris.size());
  for (size_t i = 0; i < f.tris.size(); ++i) {
    Triangle t;
    t.material = f.tri_material[i];
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = f.verts[f.tris[i][k]];
      // y-up files are turned to z-up exactly (a permutation and a negation: no rounding).
      t.p[k] = up_axis == 'y' ? Vec3{v.x, -v.z, v.y} : v;
    }
    s.tris.push_back(t);
  }
  frame_camera(s);
  return s;
}

std::string find_demo_mesh(const std::string& name) {
  std::string file = name == "bunny"       ? "bunny00.off"
                     : name == "dragon"    ? "ChineseDragon-10kv.off"
                     : name == "armadillo" ? "armadillo.off"
                                           : "";
  if (file.empty()) return "";
  const std::string rel = "data/meshes/" + file;
  std::vector<std::string> dirs;
  if (const char* d = std::getenv("RU_MESH_DIR")) dirs.push_back(d);
  std::string cache;
  if (const char* d = std::getenv("RU_CACHE_DIR")) cache = d;
  else if (const char* x = std::getenv("XDG_CACHE_HOME")) cache = std::string(x) + "/rayunits";
  else if (const char* h = std::getenv("HOME")) cache = std::string(h) + "/.cache/rayunits";
  else cache = "/tmp/rayunits-cache";
  for (const auto& d : dirs)
    if (file_exists(d + "/" + file)) return d + "/" + file;
  if (file_exists(cache + "/" + rel)) return cache + "/" + rel;
  // libcgal-demo ships the meshes inside a tarball: extract the one file on first use.
  const std::string tarball = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (!file_exists(tarball)) return "";
  std::string cmd = "mkdir -p '" + cache + "' && tar -xzf " + tarball + " -C '" + cache + "' " + rel + " 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) return "";
  return file_exists(cache + "/" + rel) ? cache + "/" + rel : "";
}

}  // namespace ru::scene
