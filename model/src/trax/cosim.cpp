// rayunits trax --cosim: the client side of the RTL co-simulation (protocol in trax/cosim.hpp).
#include "rayunits/trax/cosim.hpp"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "rayunits/noise/fixed.hpp"
#include "rayunits/num/format.hpp"
#include "rayunits/trax/thread.hpp"
#include "rayunits/util/process.hpp"

namespace ru::trax::cosim {

namespace fs = std::filesystem;

const std::vector<FpUnit>& fp_units() {
  static const std::vector<FpUnit> u = {{"fp_add", Unit::FpAdd, static_cast<uint8_t>(Op::FAdd)},
                                        {"fp_mul", Unit::FpMul, static_cast<uint8_t>(Op::FMul)},
                                        {"fp_div", Unit::FpDiv, static_cast<uint8_t>(Op::FDiv)},
                                        {"fp_sqrt", Unit::FpSqrt, static_cast<uint8_t>(Op::FSqrt)},
                                        {"fp_cmp", Unit::FpCmp, static_cast<uint8_t>(Op::FCmp)},
                                        {"fp_fma", Unit::FpFma, static_cast<uint8_t>(Op::FFma)}};
  return u;
}

std::vector<FpUnit> chip_fp_units(const Config& c) {
  std::vector<FpUnit> v;
  for (const FpUnit& u : fp_units())
    if (unit_on_chip(c, u.unit)) v.push_back(u);
  return v;
}

std::string header_line(const Config& c, bool fp) {
  const std::string fmt = c.format == "float" ? "e8m23" : c.format;
  auto unit = [&](Unit u, const std::string& algo) {
    const UnitCfg& k = c.unit(u);
    return algo + ":" + std::to_string(k.latency) + ":" + std::to_string(k.count * k.width);
  };
  std::ostringstream o;
  o << kProtocol << " format=" << fmt << " tms=" << c.tms << " box=" << unit(Unit::Box, c.box)
    << " tri=" << unit(Unit::Tri, c.tri) << " noise=" << unit(Unit::Noise, c.noise);
  if (fp)
    for (const FpUnit& u : chip_fp_units(c)) o << " " << u.name << "=" << unit(u.unit, "fp");
  return o.str();
}

std::vector<std::pair<const synth::UnitSpec*, synth::UnitConfig>> companion_units(const Config& c, bool fp) {
  num::Format f = num::Format::parse(c.format == "float" ? "e8m23" : c.format);
  auto at = [&](const char* unit, Unit u, std::map<std::string, long long> params) {
    const synth::UnitSpec* s = &synth::find_unit(unit);
    synth::UnitConfig k;
    k.fmt = f;
    k.stages = c.unit(u).latency;
    k.params = std::move(params);
    return std::make_pair(s, k);
  };
  std::vector<std::pair<const synth::UnitSpec*, synth::UnitConfig>> v;
  v.push_back(at("ray_box", Unit::Box, {{"OptConservative", c.box == "conservative" ? 1 : 0}}));
  if (c.tri == "mt")
    v.push_back(at("ray_tri_mt", Unit::Tri, {{"OptEpsTest", 0}, {"OptVolOut", 0}}));
  else
    v.push_back(at("ray_tri_robust", Unit::Tri, {{"OptTieBreak", 0}, {"OptEpsTest", 0}, {"OptVolOut", 0}}));
  // the chip's noise unit: default_config of its datapath (kernel.cpp, the renderer's Tracer)
  const std::string nu = noise_unit(c);
  const noise::FixedConfig nc =
      noise::default_config(nu == "noise" ? noise::NoiseDatapath::kFull : noise::NoiseDatapath::kTrunc);
  v.push_back(at(nu.c_str(), Unit::Noise, {{"FracBits", nc.frac_bits}, {"IntBits", nc.int_bits}, {"OutW", nc.out_w}}));
  if (fp)
    for (const FpUnit& u : chip_fp_units(c)) v.push_back(at(u.name, u.unit, {}));
  return v;
}

std::string default_executable() {
  if (const char* e = std::getenv("RU_TRAX_COSIM"); e && *e) return e;
  const std::string exe = util::self_exe();
  if (exe.empty()) return "tb_trax_cosim";
  const fs::path self = exe;
  // <build>/model/cli/rayunits -> <build>/tb/trax/tb_trax_cosim
  return (self.parent_path().parent_path().parent_path() / "tb" / "trax" / "tb_trax_cosim").string();
}

// The child's destructor closes the pipes, sends SIGTERM if it still runs and reaps it.
Client::~Client() = default;

namespace {
// Reads one line (without '\n'); false at EOF before any character.
bool read_line(int fd, std::string& line) {
  line.clear();
  char ch;
  for (;;) {
    const ssize_t n = ::read(fd, &ch, 1);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return !line.empty();
    if (ch == '\n') return true;
    line += ch;
  }
}
}  // namespace

void Client::start(const Config& cfg) {
  if (cfg.texture == "unit")
    throw std::runtime_error("--cosim: the texture unit is not co-simulated in a chip run (chip.texture = \"unit\"; "
                             "ru_texture is verified by ctest -R texture_); run with texture = \"shader\"");
  std::error_code ec;
  if (!fs::exists(exe_, ec) || ::access(exe_.c_str(), X_OK) != 0)
    throw std::runtime_error("--cosim: the RTL co-simulation executable " + exe_ +
                             " is not built (build the target tb_trax_cosim, or set RU_TRAX_COSIM)");
  std::signal(SIGPIPE, SIG_IGN);  // a companion that stopped at a mismatch: write() gives EPIPE
  // stdin and stdout are pipes to us, stderr is ours; it stays in our process group (Ctrl-C
  // ends both) and is not stopped by the interrupt flag (it ends when its input does).
  util::ProcessOptions po;
  po.in = util::Redirect::capture();
  po.out = util::Redirect::capture();
  po.new_group = false;
  po.stop_on_interrupt = false;
  try {
    child_ = std::make_unique<util::Child>(std::vector<std::string>{exe_, "--serve"}, po);
  } catch (const util::ProcessError& e) {
    throw std::runtime_error(std::string("--cosim: ") + e.what());
  }
  if (!child_->started()) throw std::runtime_error("--cosim: " + child_->wait().error);
  to_ = child_->in_fd();
  from_ = child_->out_fd();
  const std::string h = header_line(cfg, fp_) + "\n";
  put(h.data(), h.size());
  flush();
  std::string line;
  if (!read_line(from_, line)) throw std::runtime_error("--cosim: " + exe_ + " ended without an answer");
  if (line.rfind("OK", 0) != 0) {
    const std::string msg = line.rfind("ERROR ", 0) == 0 ? line.substr(6) : line;
    throw std::runtime_error("--cosim: " + msg);
  }
  ok_line_ = line.size() > 3 ? line.substr(3) : "";
}

void Client::put(const void* p, size_t n) {
  const char* c = static_cast<const char*>(p);
  buf_.insert(buf_.end(), c, c + n);
  if (buf_.size() >= (1u << 16)) flush();
}

void Client::flush() {
  size_t off = 0;
  while (off < buf_.size() && !failed_) {
    const ssize_t n = ::write(to_, buf_.data() + off, buf_.size() - off);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      failed_ = true;  // the companion stopped (a mismatch): finish() collects its report
      break;
    }
    off += static_cast<size_t>(n);
  }
  buf_.clear();
}

void Client::issue(const UnitIssue& u) {
  if (failed_) return;
  const int nin = unit_inputs(u.op), nout = unit_outputs(u.op);
  if (!u.data) throw std::logic_error("--cosim: a unit operation without recorded operands");
  Record r{};
  r.cycle = u.cycle;
  r.item = u.item;
  r.index = u.index;
  r.tm = static_cast<uint16_t>(u.tm);
  r.tp = static_cast<uint16_t>(u.tp);
  r.slot = static_cast<uint16_t>(u.slot);
  r.op = static_cast<uint8_t>(u.op);
  r.nwords = static_cast<uint8_t>(nin + nout);
  put(&r, sizeof r);
  const bool counted = inject_op_ < 0 || static_cast<int>(u.op) == inject_op_;
  if (inject_ >= 0 && counted && sent_ == static_cast<uint64_t>(inject_)) {
    uint64_t w[32];
    std::memcpy(w, u.data, sizeof(uint64_t) * (nin + nout));
    w[nin + (u.op == Op::Box ? 1 : u.op == Op::Tri ? 2 : 0)] ^= 1;  // box t_enter, tri t, noise value, FP y
    put(w, sizeof(uint64_t) * (nin + nout));
  } else {
    put(u.data, sizeof(uint64_t) * (nin + nout));
  }
  if (counted) ++sent_;
}

Outcome Client::finish(uint64_t last_cycle) {
  Outcome o;
  if (!failed_) {
    Record r{};
    r.cycle = last_cycle;
    r.op = kEndOp;
    put(&r, sizeof r);
    flush();
  }
  child_->close_in();
  to_ = from_ = -1;
  const util::ProcessResult r = child_->wait();  // the rest of its stdout, its exit status
  std::string text = r.out;
  const int st = r.term_signal ? r.term_signal : r.exit_code << 8;  // as waitpid's status
  while (!text.empty() && text.back() == '\n') text.pop_back();
  const bool exited_ok = !r.term_signal && r.exit_code == 0;
  o.ok = exited_ok && text.rfind("DONE", 0) == 0;
  o.summary = text.empty() ? "the co-simulation process ended without a verdict (status " + std::to_string(st) + ")"
                           : text;
  if (o.ok) {
    const auto p = text.find("compared=");
    if (p != std::string::npos) o.compared = std::strtoull(text.c_str() + p + 9, nullptr, 10);
  }
  return o;
}

}  // namespace ru::trax::cosim
