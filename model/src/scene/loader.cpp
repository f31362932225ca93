// Mesh loading through Assimp, and locating the CGAL demo meshes.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "rayunits/scene/scene.hpp"

namespace ru::scene {
namespace {

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s.empty() ? std::string("unknown error") : s;
}

bool file_exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
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

// The Assimp import proper (runs in the sandbox child, see load_mesh).
Scene import_in_process(const std::string& path, char up_axis) {
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
  Scene s;
  s.name = path;
  for (unsigned i = 0; i < as->mNumMaterials; ++i) {
    Material m;
    m.name = "mesh" + std::to_string(i);
    aiColor4D c;
    if (as->mMaterials[i] && as->mMaterials[i]->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS &&
        std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && (c.r + c.g + c.b) > 0.05)
      m.color = {std::min(1.0, std::max(0.0, double(c.r))), std::min(1.0, std::max(0.0, double(c.g))),
                 std::min(1.0, std::max(0.0, double(c.b)))};
    s.materials.push_back(m);
  }
  if (s.materials.empty()) s.materials.push_back(Material{"mesh0", MaterialKind::Constant, {0.8, 0.8, 0.8}, {}, 1});
  for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
    const aiMesh* m = as->mMeshes[mi];
    if (!m || !(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !m->mVertices) continue;
    uint32_t mat = m->mMaterialIndex < s.materials.size() ? m->mMaterialIndex : 0;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3 || !face.mIndices) continue;
      Triangle t;
      t.material = mat;
      for (int k = 0; k < 3; ++k) {
        unsigned vi = face.mIndices[k];
        if (vi >= m->mNumVertices) throw SceneError("malformed mesh '" + path + "': vertex index out of range");
        const aiVector3D& v = m->mVertices[vi];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
          throw SceneError("malformed mesh '" + path + "': non-finite vertex coordinate");
        // y-up files are turned to z-up exactly (a permutation and a negation: no rounding).
        t.p[k] = up_axis == 'y' ? Vec3{v.x, -double(v.z), v.y} : Vec3{v.x, v.y, v.z};
      }
      s.tris.push_back(t);
    }
  }
  if (s.tris.empty()) throw SceneError("mesh '" + path + "' contains no triangles");
  return s;
}

// --- sandbox: Assimp runs in a forked child that sends the triangles back through a pipe, so
// that a hang (Assimp 5.2.5 loops forever on a PLY header cut short) or a crash inside the
// importer becomes one error line instead of taking the program down.
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

std::string encode(const Scene& s) {
  Buf b;
  b.put(uint32_t{0});
  b.put(static_cast<uint64_t>(s.materials.size()));
  for (const auto& m : s.materials) b.put(m.color);
  b.put(static_cast<uint64_t>(s.tris.size()));
  for (const auto& t : s.tris) {
    for (const auto& p : t.p) b.put(p);
    b.put(t.material);
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

Scene run_sandboxed(const std::string& path, char up_axis, double timeout_s) {
  int fds[2];
  if (::pipe(fds) != 0) return import_in_process(path, up_axis);  // no sandbox available
  std::fflush(nullptr);
  pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return import_in_process(path, up_axis);
  }
  if (pid == 0) {  // child: import, send, _exit (no destructors, no atexit handlers)
    ::close(fds[0]);
    std::string out;
    try {
      out = encode(import_in_process(path, up_axis));
    } catch (const std::exception& e) {
      Buf b;
      b.put(uint32_t{1});
      std::string m = e.what();
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
  bool timed_out = false;
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
  }
  ::close(fds[0]);
  if (timed_out) ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (timed_out)
    throw SceneError("cannot load mesh '" + path + "': the importer did not finish within " +
                     std::to_string(static_cast<int>(timeout_s)) + " s (malformed file?)");
  if (WIFSIGNALED(status))
    throw SceneError("cannot load mesh '" + path + "': the importer crashed (signal " +
                     std::to_string(WTERMSIG(status)) + "; malformed file?)");
  Reader rd{data};
  uint32_t tag = 9;
  if (!rd.get(&tag)) throw SceneError("cannot load mesh '" + path + "': the importer sent nothing");
  if (tag == 1) {
    uint64_t len = 0;
    rd.get(&len);
    throw SceneError(one_line(data.substr(rd.off, static_cast<size_t>(len))));
  }
  Scene s;
  s.name = path;
  uint64_t nm = 0, nt = 0;
  bool ok = rd.get(&nm) && nm < (1u << 20);
  for (uint64_t i = 0; ok && i < nm; ++i) {
    Material m;
    m.name = "mesh" + std::to_string(i);
    ok = rd.get(&m.color);
    s.materials.push_back(m);
  }
  ok = ok && rd.get(&nt) && nt <= data.size();
  for (uint64_t i = 0; ok && i < nt; ++i) {
    Triangle t;
    ok = rd.get(&t.p[0]) && rd.get(&t.p[1]) && rd.get(&t.p[2]) && rd.get(&t.material);
    s.tris.push_back(t);
  }
  if (!ok || rd.off != data.size()) throw SceneError("cannot load mesh '" + path + "': truncated importer reply");
  return s;
}

}  // namespace

void set_mesh_load_timeout(double seconds) { g_timeout_override = seconds; }

Scene load_mesh(const std::string& path, char up_axis) {
  if (up_axis != 'y' && up_axis != 'z') throw SceneError("up axis must be 'y' or 'z'");
  if (!file_exists(path)) throw SceneError("cannot open mesh file '" + path + "': no such file");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw SceneError("cannot open mesh file '" + path + "': not readable");
  // PLY headers must end: Assimp 5.2.5 never returns on a header cut short.
  std::string head(65536, '\0');
  probe.read(&head[0], static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(probe.gcount()));
  if (head.compare(0, 3, "ply") == 0 && head.find("end_header") == std::string::npos)
    throw SceneError("malformed PLY file '" + path + "': header without end_header");
  struct stat st;
  ::stat(path.c_str(), &st);
  double timeout = g_timeout_override > 0 ? g_timeout_override : 30.0 + 2.0 * static_cast<double>(st.st_size) / 1e6;
  if (const char* e = std::getenv("RU_MESH_TIMEOUT")) timeout = std::max(0.1, std::atof(e));
  Scene s = run_sandboxed(path, up_axis, timeout);
  if (s.tris.empty()) throw SceneError("mesh '" + path + "' contains no triangles");
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
