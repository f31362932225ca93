// tb_trax_cosim: the RTL side of `rayunits trax --cosim` (protocol: model/include/rayunits/trax/
// cosim.hpp; design: docs/TRAX.md "RTL co-simulation").
//
//   tb_trax_cosim --serve   read the header and the operation stream on stdin, answer on stdout
//   tb_trax_cosim --list    print the RTL configurations linked into this executable
//
// One Verilated RTL instance per (TM, unit class, issue slot), created (and reset for 3 cycles)
// at its first operation. Every instance follows the scoreboard contract of tb/README.md: in
// simulated cycle t it drives in_valid_i and the inputs of the operation issued in cycle t (or
// in_valid_i = 0), evaluates with clk_i = 0, checks the outputs, then gives the rising edge.
// out_valid_o must be 1 exactly in the cycle issue + Stages (= the latency the timing model
// used: the configuration check guarantees Stages == latency), and then every output bit must
// equal the golden model's output sent with the operation. While an instance has operations in
// flight it is clocked every cycle; an instance with an empty pipeline skips idle cycles (its
// valid pipeline is all zeros, so no result can be lost or invented in them).
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/tb/dut.hpp"
#include "rayunits/trax/cosim.hpp"
#include "rayunits/trax/thread.hpp"

using ru::tb::ConfigDesc;
using ru::tb::Port;
using ru::trax::Op;
namespace cosim = ru::trax::cosim;

namespace {

struct Field {
  const char* port;
  int word;   // first data word
  int n;      // 1 scalar or 3 (a vector packed {z, y, x}, x in the low W bits)
  bool fp;    // a format value (printed in decimal too)
  const char* name;
};
// Data words of each op (thread.hpp kBoxIn...): inputs, then outputs.
const std::vector<Field> kBoxInF = {{"org_i", 0, 3, true, "o"},     {"rdir_i", 3, 3, true, "inv"},
                                    {"bmin_i", 6, 3, true, "lo"},   {"bmax_i", 9, 3, true, "hi"},
                                    {"tmin_i", 12, 1, true, "t_min"}, {"tmax_i", 13, 1, true, "t_max"}};
const std::vector<Field> kBoxOutF = {
    {"hit_o", 14, 1, false, "hit"}, {"t_enter_o", 15, 1, true, "t_enter"}, {"t_exit_o", 16, 1, true, "t_exit"}};
const std::vector<Field> kTriInF = {{"a_i", 0, 3, true, "a"},         {"d_i", 3, 3, true, "d"},
                                    {"p0_i", 6, 3, true, "p0"},       {"p1_i", 9, 3, true, "p1"},
                                    {"p2_i", 12, 3, true, "p2"},      {"tmin_i", 15, 1, true, "t_min"},
                                    {"tmax_i", 16, 1, true, "t_max"}};
const std::vector<Field> kTriOutF = {{"hit_o", 17, 1, false, "hit"},   {"why_o", 18, 1, false, "why"},
                                     {"t_o", 19, 1, true, "t"},        {"beta_o", 20, 1, true, "beta"},
                                     {"gamma_o", 21, 1, true, "gamma"}};
const std::vector<Field> kNoiseInF = {{"x_i", 0, 1, false, "x"}, {"y_i", 1, 1, false, "y"}, {"z_i", 2, 1, false, "z"}};
const std::vector<Field> kNoiseOutF = {{"value_o", 3, 1, false, "value"}};

struct UnitSel {
  Op op = Op::Box;
  const ConfigDesc* desc = nullptr;
  std::string algo;
  int latency = 0, slots = 0;
  const std::vector<Field>* in = nullptr;
  const std::vector<Field>* out = nullptr;
  std::string rtl;  // "ray_tri_robust e8m23_s29"
};

struct Pending {
  uint64_t due;
  cosim::Record rec;
  std::vector<uint64_t> w;
};

struct Inst {
  const UnitSel* u = nullptr;
  int tm = 0, slot = 0;
  std::unique_ptr<ru::tb::Dut> dut;
  Port clk, rst, in_valid, out_valid;
  std::vector<Port> in, out;
  uint64_t now = 0;  // next cycle to simulate
  std::deque<Pending> q;
};

ru::num::Format g_fmt;
int g_w = 32;
std::map<Op, UnitSel> g_units;
std::vector<std::unique_ptr<Inst>> g_inst;  // index: (op, tm, slot)
std::map<std::tuple<int, int, int>, Inst*> g_by_key;
uint64_t g_compared = 0, g_by_op[3] = {0, 0, 0}, g_rtl_cycles = 0;
// Planted timing error for the tests: $RU_TRAX_COSIM_LATENCY_DELTA = d expects every result d
// cycles later than the latency (the out_valid_o check must catch it).
int g_latency_delta = 0;

void reply(const std::string& s) {
  std::fputs(s.c_str(), stdout);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}
[[noreturn]] void fail_line(const std::string& msg) {
  reply("ERROR " + msg);
  std::exit(2);
}

std::string hex(uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof b, "0x%" PRIx64, v);
  return b;
}
std::string value_text(const Field& f, uint64_t v) {
  if (!f.fp) return hex(v) + " (" + std::to_string(v) + ")";
  char b[64];
  std::snprintf(b, sizeof b, "%s (%.9g)", hex(v).c_str(), ru::num::to_double(g_fmt, v));
  return b;
}
std::string field_text(const Field& f, const uint64_t* w) {
  if (f.n == 1) return value_text(f, w[f.word]);
  return "(" + value_text(f, w[f.word]) + ", " + value_text(f, w[f.word + 1]) + ", " + value_text(f, w[f.word + 2]) +
         ")";
}

// Packs the field's values into little-endian 64-bit words for Port::set_words.
void drive(Port& p, const Field& f, const uint64_t* w) {
  uint64_t words[4] = {0, 0, 0, 0};
  const int width = f.n == 1 ? p.bits() : g_w;
  for (int k = 0; k < f.n; ++k) {
    const uint64_t v = w[f.word + k] & (width >= 64 ? ~0ull : ((1ull << width) - 1));
    const int bit = k * width;
    words[bit / 64] |= v << (bit % 64);
    if (bit % 64 && bit % 64 + width > 64) words[bit / 64 + 1] |= v >> (64 - bit % 64);
  }
  p.set_words(words, 4);
}
void read_field(const Port& p, const Field& f, uint64_t* vals) {
  uint64_t words[4] = {0, 0, 0, 0};
  p.get_words(words);
  const int width = f.n == 1 ? p.bits() : g_w;
  const uint64_t m = width >= 64 ? ~0ull : ((1ull << width) - 1);
  for (int k = 0; k < f.n; ++k) {
    const int bit = k * width;
    uint64_t v = words[bit / 64] >> (bit % 64);
    if (bit % 64 && bit % 64 + width > 64) v |= words[bit / 64 + 1] << (64 - bit % 64);
    vals[k] = v & m;
  }
}

const char* op_label(Op op) { return op == Op::Box ? "BOX" : op == Op::Tri ? "TRI" : "NOISE"; }

[[noreturn]] void mismatch(const Inst& in, uint64_t cycle, const Pending* p, const std::string& what,
                           const std::vector<uint64_t>* rtl) {
  std::ostringstream o;
  o << "MISMATCH in cycle " << cycle << ": " << what << "\n";
  if (p) {
    const cosim::Record& r = p->rec;
    o << "  operation: " << op_label(static_cast<Op>(r.op)) << " issued in cycle " << r.cycle << " by TM " << r.tm
      << ", TP " << r.tp << " (work item " << r.item << ", instruction #" << r.index << " of its stream), unit slot "
      << r.slot << ", RTL " << in.u->rtl << " (latency " << in.u->latency << ")\n";
    for (const Field& f : *in.u->in) o << "  in  " << f.name << " = " << field_text(f, p->w.data()) << "\n";
    for (const Field& f : *in.u->out) {
      o << "  out " << f.name << ": golden " << field_text(f, p->w.data());
      if (rtl) {
        const uint64_t got = (*rtl)[f.word];
        o << ", RTL " << value_text(f, got);
        if (got != p->w[f.word]) o << "  <-- differs (xor " << hex(got ^ p->w[f.word]) << ")";
      }
      o << "\n";
    }
  } else {
    o << "  RTL " << in.u->rtl << " of TM " << in.tm << ", unit slot " << in.slot << "\n";
  }
  o << "  (" << g_compared << " operations compared equal before this one)";
  reply(o.str());
  std::exit(1);
}

// Simulates cycle `t` of an instance, issuing `p` (may be null) in it.
void step(Inst& in, uint64_t t, Pending* issue) {
  if (issue) {
    const uint64_t* w = issue->w.data();
    for (size_t i = 0; i < in.in.size(); ++i) drive(in.in[i], (*in.u->in)[i], w);
    in.in_valid.set(1);
    issue->due = t + static_cast<uint64_t>(in.u->latency + g_latency_delta);
    in.q.push_back(std::move(*issue));
  } else {
    in.in_valid.set(0);
  }
  in.clk.set(0);
  in.dut->eval();
  const bool v = in.out_valid.get() != 0;
  if (!in.q.empty() && in.q.front().due == t) {
    Pending& p = in.q.front();
    // read every output into a word vector laid out like the golden words
    std::vector<uint64_t> got(p.w.size(), 0);
    for (size_t i = 0; i < in.out.size(); ++i) {
      const Field& f = (*in.u->out)[i];
      read_field(in.out[i], f, &got[f.word]);
    }
    if (!v) mismatch(in, t, &p, "out_valid_o = 0 when the result is due (issue + latency)", nullptr);
    for (const Field& f : *in.u->out)
      for (int k = 0; k < f.n; ++k)
        if (got[f.word + k] != p.w[f.word + k])
          mismatch(in, t, &p, std::string("RTL output ") + f.port + " differs from the golden model", &got);
    ++g_compared;
    ++g_by_op[p.rec.op - static_cast<int>(Op::Box)];
    in.q.pop_front();
  } else if (v) {
    mismatch(in, t, nullptr, "out_valid_o = 1 but no result is due in this cycle", nullptr);
  }
  in.clk.set(1);
  in.dut->eval();
  in.now = t + 1;
  ++g_rtl_cycles;
}

Inst& instance(Op op, int tm, int slot, uint64_t cycle) {
  const auto key = std::make_tuple(static_cast<int>(op), tm, slot);
  auto it = g_by_key.find(key);
  if (it != g_by_key.end()) return *it->second;
  auto in = std::make_unique<Inst>();
  in->u = &g_units.at(op);
  in->tm = tm;
  in->slot = slot;
  ru::tb::DutOptions o;
  o.seed = 1 + g_inst.size();
  in->dut = in->u->desc->make(o);
  const auto& pm = in->dut->ports();
  in->clk = pm.get("clk_i");
  in->rst = pm.get("rst_ni");
  in->in_valid = pm.get("in_valid_i");
  in->out_valid = pm.get("out_valid_o");
  for (const Field& f : *in->u->in) in->in.push_back(pm.get(f.port));
  for (const Field& f : *in->u->out) in->out.push_back(pm.get(f.port));
  // reset: 3 cycles with rst_ni = 0
  in->in_valid.set(0);
  in->rst.set(0);
  for (int i = 0; i < 3; ++i) {
    in->clk.set(0);
    in->dut->eval();
    in->clk.set(1);
    in->dut->eval();
  }
  in->rst.set(1);
  in->now = cycle;
  Inst* raw = in.get();
  g_inst.push_back(std::move(in));
  g_by_key[key] = raw;
  return *raw;
}

// Simulates every busy instance up to (not including) cycle t; idle ones jump to t.
void advance_all(uint64_t t) {
  for (auto& p : g_inst) {
    Inst& in = *p;
    while (in.now < t && !in.q.empty()) step(in, in.now, nullptr);
    if (in.now < t) in.now = t;
  }
}

bool read_exact(void* p, size_t n) {
  return std::fread(p, 1, n, stdin) == n;
}

const ConfigDesc* find(const std::string& unit, const std::map<std::string, int64_t>& want, std::string& have) {
  const ConfigDesc* hit = nullptr;
  for (const ConfigDesc& d : ru::tb::registered_configs()) {
    if (d.unit != unit) continue;
    have += (have.empty() ? "" : ", ") + d.full_name();
    bool ok = true;
    for (const auto& [k, v] : want)
      if (d.param(k, k.rfind("Opt", 0) == 0 ? 0 : -1) != v) ok = false;
    if (ok && !hit) hit = &d;
  }
  return hit;
}

// Parses "algo:latency:slots".
void unit_spec(const std::string& key, const std::string& v, UnitSel& u) {
  std::istringstream s(v);
  std::string lat, slots;
  if (!std::getline(s, u.algo, ':') || !std::getline(s, lat, ':') || !std::getline(s, slots))
    fail_line("bad header field " + key + "=" + v);
  u.latency = std::atoi(lat.c_str());
  u.slots = std::atoi(slots.c_str());
}

void configure(const std::string& header) {
  std::istringstream s(header);
  std::string w1, w2;
  s >> w1 >> w2;
  if (w1 + " " + w2 != cosim::kProtocol) fail_line("protocol mismatch: got '" + w1 + " " + w2 + "'");
  std::map<std::string, std::string> kv;
  for (std::string tok; s >> tok;) {
    const auto eq = tok.find('=');
    if (eq == std::string::npos) fail_line("bad header token '" + tok + "'");
    kv[tok.substr(0, eq)] = tok.substr(eq + 1);
  }
  try {
    g_fmt = ru::num::Format::parse(kv["format"]);
  } catch (const std::exception& e) {
    fail_line(e.what());
  }
  g_w = g_fmt.width();
  UnitSel box, tri, noise;
  box.op = Op::Box;
  tri.op = Op::Tri;
  noise.op = Op::Noise;
  unit_spec("box", kv["box"], box);
  unit_spec("tri", kv["tri"], tri);
  unit_spec("noise", kv["noise"], noise);
  const std::map<std::string, int64_t> fp = {{"ExpW", g_fmt.exp_bits},
                                             {"FracW", g_fmt.frac_bits},
                                             {"Subnormals", g_fmt.subnormals ? 1 : 0},
                                             {"Round", static_cast<int>(g_fmt.round)}};
  const std::string fmt_name = g_fmt.name();
  auto pick = [&](UnitSel& u, const std::string& unit, std::map<std::string, int64_t> want, const std::string& what) {
    want["Stages"] = u.latency;
    std::string have;
    u.desc = find(unit, want, have);
    if (!u.desc)
      fail_line("no RTL build of " + what + " at latency (Stages) " + std::to_string(u.latency) +
                " in tb_trax_cosim (built: " + have + "; add it to RU_TRAX_COSIM_* in tb/trax/CMakeLists.txt)");
    u.rtl = u.desc->full_name();
  };
  if (box.algo != "plain" && box.algo != "conservative") fail_line("unknown box mode " + box.algo);
  {
    auto want = fp;
    want["OptConservative"] = box.algo == "conservative" ? 1 : 0;
    pick(box, "ray_box", want, "ray_box " + fmt_name + (box.algo == "conservative" ? " conservative" : ""));
  }
  if (tri.algo != "robust" && tri.algo != "mt") fail_line("unknown tri algorithm " + tri.algo);
  {
    auto want = fp;
    want["OptTieBreak"] = 0;
    want["OptEpsTest"] = 0;
    want["OptVolOut"] = 0;
    if (tri.algo == "mt") want.erase("OptTieBreak");
    pick(tri, tri.algo == "robust" ? "ray_tri_robust" : "ray_tri_mt", want, "ray_tri_" + tri.algo + " " + fmt_name);
  }
  if (noise.algo != "fixed")
    fail_line("chip.noise = " + noise.algo + " has no RTL (the noise unit implements noise = fixed)");
  pick(noise, "noise", {{"FracBits", 8}, {"IntBits", 8}, {"OutW", 10}}, "noise (FracBits 8, IntBits 8, OutW 10)");
  box.in = &kBoxInF;
  box.out = &kBoxOutF;
  tri.in = &kTriInF;
  tri.out = &kTriOutF;
  noise.in = &kNoiseInF;
  noise.out = &kNoiseOutF;
  g_units[Op::Box] = box;
  g_units[Op::Tri] = tri;
  g_units[Op::Noise] = noise;
  reply("OK RTL " + box.rtl + ", " + tri.rtl + ", " + noise.rtl);
}

int serve() {
  std::string header;
  for (int ch; (ch = std::fgetc(stdin)) != EOF && ch != '\n';) header += static_cast<char>(ch);
  if (header.empty()) fail_line("no header on stdin");
  configure(header);
  uint64_t last = 0;
  std::vector<uint64_t> words;
  for (;;) {
    cosim::Record r;
    if (!read_exact(&r, sizeof r)) {
      reply("MISMATCH the operation stream ended without its end record (the timing model stopped)");
      return 1;
    }
    if (r.op == cosim::kEndOp) {
      advance_all(r.cycle + 1);
      for (auto& p : g_inst)
        if (!p->q.empty())
          mismatch(*p, r.cycle, &p->q.front(), "a result is due after the run's last cycle", nullptr);
      break;
    }
    if (r.cycle < last) fail_line("operations out of cycle order");
    last = r.cycle;
    const Op op = static_cast<Op>(r.op);
    if (op != Op::Box && op != Op::Tri && op != Op::Noise) fail_line("bad op in the stream");
    const int n = ru::trax::unit_inputs(op) + ru::trax::unit_outputs(op);
    if (r.nwords != n) fail_line("bad record length");
    Pending p;
    p.rec = r;
    p.w.resize(n);
    if (!read_exact(p.w.data(), sizeof(uint64_t) * n)) fail_line("truncated record");
    const UnitSel& u = g_units.at(op);
    if (r.slot >= u.slots) fail_line("unit slot out of range");
    advance_all(r.cycle);
    Inst& in = instance(op, r.tm, r.slot, r.cycle);
    if (in.now != r.cycle) fail_line("two operations in one cycle on one unit slot");
    step(in, r.cycle, &p);
  }
  std::ostringstream o;
  o << "DONE compared=" << g_compared << " box=" << g_by_op[0] << " tri=" << g_by_op[1] << " noise=" << g_by_op[2]
    << " rtl_instances=" << g_inst.size() << " rtl_cycles=" << g_rtl_cycles;
  reply(o.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string a = argc > 1 ? argv[1] : "";
  if (const char* d = std::getenv("RU_TRAX_COSIM_LATENCY_DELTA")) g_latency_delta = std::atoi(d);
  if (a == "--serve") return serve();
  if (a == "--list") {
    for (const ConfigDesc& d : ru::tb::registered_configs()) {
      std::printf("%s:", d.full_name().c_str());
      for (const auto& [k, v] : d.params) std::printf(" %s=%lld", k.c_str(), static_cast<long long>(v));
      std::printf("\n");
    }
    return 0;
  }
  std::fprintf(stderr,
               "usage: tb_trax_cosim --serve | --list\n"
               "  the RTL co-simulation companion of `rayunits trax --cosim` (docs/TRAX.md); --list prints the\n"
               "  RTL configurations linked into it\n");
  return 2;
}
