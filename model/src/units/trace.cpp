// Binary trace reader and writer (format: units/trace.hpp, docs/UNITS.md).
#include "rayunits/units/trace.hpp"

#include <cerrno>
#include <cstring>

namespace ru::units {
namespace {

void put_u32(unsigned char* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
void put_u64(unsigned char* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
uint32_t get_u32(const unsigned char* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(p[i]) << (8 * i);
  return v;
}
uint64_t get_u64(const unsigned char* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}
void put_f64(unsigned char* p, double x) {
  uint64_t u;
  std::memcpy(&u, &x, 8);
  put_u64(p, u);
}
double get_f64(const unsigned char* p) {
  uint64_t u = get_u64(p);
  double x;
  std::memcpy(&x, &u, 8);
  return x;
}
void put_vec(unsigned char*& p, const Vec3d& v) {
  for (int k = 0; k < 3; ++k, p += 8) put_f64(p, v[k]);
}
Vec3d get_vec(const unsigned char*& p) {
  Vec3d v;
  for (int k = 0; k < 3; ++k, p += 8) v[k] = get_f64(p);
  return v;
}

void make_header(unsigned char* h, uint64_t ntri, uint64_t nbox) {
  std::memcpy(h, kTraceMagic, 8);
  put_u32(h + 8, kTraceVersion);
  put_u32(h + 12, kTraceHeaderBytes);
  put_u64(h + 16, ntri);
  put_u64(h + 24, nbox);
}

}  // namespace

TraceWriter::TraceWriter(const std::string& path) : path_(path) {
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_) throw TraceError("trace " + path + ": cannot create: " + std::strerror(errno));
  unsigned char h[kTraceHeaderBytes];
  make_header(h, 0, 0);
  put(h, sizeof h);
}

TraceWriter::~TraceWriter() {
  try {
    close();
  } catch (...) {
  }
}

void TraceWriter::put(const void* p, size_t n) {
  if (std::fwrite(p, 1, n, f_) != n)
    throw TraceError("trace " + path_ + ": write failed: " + std::strerror(errno));
}

void TraceWriter::write(const TriRecord& r) {
  unsigned char b[kTraceTriBytes];
  put_u32(b, kTraceKindTri);
  put_u32(b + 4, 0);
  unsigned char* p = b + 8;
  put_vec(p, r.a);
  put_vec(p, r.d);
  put_vec(p, r.p0);
  put_vec(p, r.p1);
  put_vec(p, r.p2);
  put_f64(p, r.t_min);
  put_f64(p + 8, r.t_max);
  put(b, sizeof b);
  ++ntri_;
}

void TraceWriter::write(const BoxRecord& r) {
  unsigned char b[kTraceBoxBytes];
  put_u32(b, kTraceKindBox);
  put_u32(b + 4, 0);
  unsigned char* p = b + 8;
  put_vec(p, r.o);
  put_vec(p, r.inv);
  put_vec(p, r.lo);
  put_vec(p, r.hi);
  put_f64(p, r.t_min);
  put_f64(p + 8, r.t_max);
  put(b, sizeof b);
  ++nbox_;
}

void TraceWriter::close() {
  if (!f_) return;
  std::FILE* f = f_;
  f_ = nullptr;
  unsigned char h[kTraceHeaderBytes];
  make_header(h, ntri_, nbox_);
  bool ok = std::fseek(f, 0, SEEK_SET) == 0 && std::fwrite(h, 1, sizeof h, f) == sizeof h;
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) throw TraceError("trace " + path_ + ": cannot finish the header: " + std::strerror(errno));
}

Trace read_trace(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw TraceError("trace " + path + ": cannot open: " + std::strerror(errno));
  std::vector<unsigned char> buf;
  unsigned char chunk[1 << 16];
  size_t n;
  while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) buf.insert(buf.end(), chunk, chunk + n);
  const bool err = std::ferror(f);
  std::fclose(f);
  if (err) throw TraceError("trace " + path + ": read error");

  auto fail = [&](size_t off, const std::string& what) {
    throw TraceError("trace " + path + ": byte " + std::to_string(off) + ": " + what);
  };
  if (buf.size() < kTraceHeaderBytes)
    fail(0, "not a rayunits trace: " + std::to_string(buf.size()) +
                " bytes, the header alone is 32 (magic RUTRACE)");
  if (std::memcmp(buf.data(), kTraceMagic, 8) != 0)
    fail(0, "not a rayunits trace: bad magic (expected \"RUTRACE\\0\")");
  const uint32_t version = get_u32(buf.data() + 8);
  if (version != kTraceVersion)
    fail(8, "unsupported trace version " + std::to_string(version) + " (this reader knows 1)");
  const uint32_t hbytes = get_u32(buf.data() + 12);
  if (hbytes != kTraceHeaderBytes)
    fail(12, "header size " + std::to_string(hbytes) + ", expected 32");
  const uint64_t want_tri = get_u64(buf.data() + 16), want_box = get_u64(buf.data() + 24);

  Trace t;
  size_t off = kTraceHeaderBytes;
  while (off < buf.size()) {
    const size_t left = buf.size() - off;
    if (left < 8) fail(off, "truncated record header (" + std::to_string(left) + " bytes left, need 8)");
    const uint32_t kind = get_u32(buf.data() + off);
    const uint32_t reserved = get_u32(buf.data() + off + 4);
    size_t need;
    if (kind == kTraceKindTri) {
      need = kTraceTriBytes;
    } else if (kind == kTraceKindBox) {
      need = kTraceBoxBytes;
    } else {
      fail(off, "unknown record kind " + std::to_string(kind) + " (1 = tri, 2 = box)");
    }
    if (reserved != 0) fail(off + 4, "reserved field of a record is " + std::to_string(reserved) + ", must be 0");
    if (left < need)
      fail(off, std::string("truncated ") + (kind == kTraceKindTri ? "tri" : "box") + " record (" +
                    std::to_string(left) + " bytes left, need " + std::to_string(need) + ")");
    const unsigned char* p = buf.data() + off + 8;
    if (kind == kTraceKindTri) {
      TriRecord r;
      r.a = get_vec(p);
      r.d = get_vec(p);
      r.p0 = get_vec(p);
      r.p1 = get_vec(p);
      r.p2 = get_vec(p);
      r.t_min = get_f64(p);
      r.t_max = get_f64(p + 8);
      t.tris.push_back(r);
    } else {
      BoxRecord r;
      r.o = get_vec(p);
      r.inv = get_vec(p);
      r.lo = get_vec(p);
      r.hi = get_vec(p);
      r.t_min = get_f64(p);
      r.t_max = get_f64(p + 8);
      t.boxes.push_back(r);
    }
    off += need;
  }
  if (t.tris.size() != want_tri || t.boxes.size() != want_box)
    fail(16, "header says " + std::to_string(want_tri) + " tri + " + std::to_string(want_box) +
                 " box records, the file holds " + std::to_string(t.tris.size()) + " + " +
                 std::to_string(t.boxes.size()) + " (writer not closed?)");
  return t;
}

void write_trace(const std::string& path, const Trace& t) {
  TraceWriter w(path);
  for (const auto& r : t.tris) w.write(r);
  for (const auto& r : t.boxes) w.write(r);
  w.close();
}

}  // namespace ru::units
