// tb_trax_cosim: the RTL side of `rayunits trax --cosim` (protocol: model/include/rayunits/trax/
// cosim.hpp; design: docs/TRAX.md "RTL co-simulation").
//
//   tb_trax_cosim --serve   read the header and the operation stream on stdin, answer on stdout
//   tb_trax_cosim --list    print the RTL configurations linked into this executable
//
// One Verilated RTL instance per (TM, unit class, issue slot), created (and reset for 3 cycles)
// at its first operation, each run by the shared scoreboard (ru::tb::Scoreboard, the one the
// unit testbenches use; contract in tb/README.md) through the registry's adapter
// (ru::tb::RegistryAdapter: ports, fields and widths from the unit registry). In simulated cycle t
// the scoreboard drives in_valid_i and the inputs of the operation issued in cycle t (or
// in_valid_i = 0 and junk inputs), evaluates with clk_i = 0, checks the outputs, then gives the
// rising edge. out_valid_o must be 1 exactly in the cycle issue + Stages (= the latency the
// timing model used: the configuration check guarantees Stages == latency), and then every
// output bit must equal the golden model's output sent with the operation (outputs the operand
// record does not carry, the triangle units' vol_o, are compared with the registry's model).
// While an instance has operations in flight it is clocked every cycle; an instance with an
// empty pipeline skips idle cycles (its valid pipeline is all zeros, so no result can be lost
// or invented in them). The operand records' word layout is trax::unit_words (thread.hpp),
// mapped onto the registry's fields by port name and checked against them.
#include <cctype>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "rayunits/num/format.hpp"
#include "rayunits/synth/units.hpp"
#include "rayunits/tb/dut.hpp"
#include "rayunits/tb/harness.hpp"
#include "rayunits/tb/registry_adapter.hpp"
#include "rayunits/trax/cosim.hpp"
#include "rayunits/trax/thread.hpp"

using ru::tb::ConfigDesc;
using ru::trax::Op;
namespace cosim = ru::trax::cosim;
namespace synth = ru::synth;

namespace {

// Every instance is reset for kResetCycles cycles of its own clock before its first operation;
// its scoreboard numbers cycles as TRaX cycle + kResetCycles (reports show TRaX cycles).
constexpr uint64_t kResetCycles = 3;

struct UnitSel {
  Op op = Op::Box;
  const ConfigDesc* desc = nullptr;
  std::string algo;
  int latency = 0, slots = 0;
  std::string rtl;  // "ray_tri_robust e8m23_s29"
  const synth::UnitSpec* spec = nullptr;
  synth::UnitConfig cfg;
  // The operand record's word of every registry input / output field (fields_for order);
  // -1 for an output the record does not carry (its expected value is the registry's model).
  std::vector<int> in_word, out_word;
};

struct Inst {
  const UnitSel* u = nullptr;
  int tm = 0, slot = 0;
  std::unique_ptr<ru::tb::Dut> dut;
  std::unique_ptr<ru::tb::RegistryAdapter> ad;
  ru::tb::RunOptions opt;
  std::unique_ptr<ru::tb::Scoreboard> sb;
  uint64_t now = 0;                  // next TRaX cycle to simulate
  std::deque<cosim::Record> issued;  // the operations issued, by issue index - first
  int64_t first = 0;
};

ru::num::Format g_fmt;
std::map<Op, UnitSel> g_units;
std::vector<std::unique_ptr<Inst>> g_inst;
std::map<std::tuple<int, int, int>, Inst*> g_by_key;  // (op, tm, slot)
uint64_t g_rtl_cycles = 0;
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

// The operation's name in messages: trax::op_name in capitals ("FADD", "BOX").
std::string op_label(Op op) {
  if (static_cast<int>(op) >= ru::trax::kOps) return "?";
  std::string s = ru::trax::op_name(op);
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}


uint64_t compared() {
  uint64_t n = 0;
  for (const auto& p : g_inst) n += p->sb->stats().checked;
  return n;
}

// The scoreboard found a mismatch in the last cycle of `in`: print it and end.
[[noreturn]] void mismatch(const Inst& in) {
  const ru::tb::Mismatch& m = in.sb->stats().errors.front();
  std::ostringstream o;
  o << "MISMATCH in cycle " << m.cycle - kResetCycles << ": ";
  switch (m.kind) {
    case ru::tb::Mismatch::Data: {
      o << "RTL output";
      const auto& outs = in.ad->outputs();
      for (size_t i = 0; i < outs.size(); ++i)
        if (m.field_mask & (1u << i)) o << " " << outs[i].name;
      o << " differs from the golden model";
      break;
    }
    case ru::tb::Mismatch::MissingValid: o << "out_valid_o = 0 when the result is due (issue + latency)"; break;
    case ru::tb::Mismatch::UnexpectedValid: o << "out_valid_o = 1 but no result is due in this cycle"; break;
    case ru::tb::Mismatch::Ready: o << "in_ready_o differs from the unit's timing"; break;  // (no TRaX unit has a handshake)
  }
  o << "\n  RTL " << in.u->rtl << " of TM " << in.tm << ", unit slot " << in.slot << " (latency " << in.u->latency
    << ")\n"
    << m.report << "  (" << compared() - (m.kind == ru::tb::Mismatch::UnexpectedValid ? 0 : 1)
    << " operations compared equal before this one)";
  reply(o.str());
  std::exit(1);
}

// Simulates TRaX cycle `t` of an instance, issuing the operation `r` with words `w` in it (null:
// nothing issued).
void step(Inst& in, uint64_t t, const cosim::Record* r, const uint64_t* w) {
  bool ok;
  if (r) {
    const UnitSel& u = *in.u;
    ru::tb::Record rec{}, exp{};
    for (size_t i = 0; i < u.in_word.size(); ++i) rec.v[i] = w[u.in_word[i]];
    in.ad->model(rec, exp);  // outputs the record does not carry
    const auto& outs = in.ad->outputs();
    for (size_t i = 0; i < u.out_word.size(); ++i)
      if (u.out_word[i] >= 0) exp.v[i] = w[u.out_word[i]] & outs[i].mask();
    in.issued.push_back(*r);
    while (in.issued.size() > static_cast<size_t>(2 * (in.sb->latency() + 2))) {
      in.issued.pop_front();
      ++in.first;
    }
    ok = in.sb->cycle(t + kResetCycles, &rec, &exp);
  } else {
    ok = in.sb->cycle(t + kResetCycles, nullptr);
  }
  in.now = t + 1;
  ++g_rtl_cycles;
  if (!ok) mismatch(in);
}

std::string item_context(const Inst& in, int64_t item) {
  if (item < in.first || item >= in.first + static_cast<int64_t>(in.issued.size())) return "";
  const cosim::Record& r = in.issued[static_cast<size_t>(item - in.first)];
  std::ostringstream o;
  o << "  operation: " << op_label(static_cast<Op>(r.op)) << " issued in cycle " << r.cycle << " by TM " << r.tm
    << ", TP " << r.tp << " (work item " << r.item << ", instruction #" << r.index << " of its stream), unit slot "
    << r.slot << ", RTL " << in.u->rtl << " (latency " << in.u->latency << ")\n";
  return o.str();
}

Inst& instance(Op op, int tm, int slot, uint64_t cycle) {
  const auto key = std::make_tuple(static_cast<int>(op), tm, slot);
  auto it = g_by_key.find(key);
  if (it != g_by_key.end()) return *it->second;
  auto in = std::make_unique<Inst>();
  Inst* raw = in.get();
  in->u = &g_units.at(op);
  in->tm = tm;
  in->slot = slot;
  ru::tb::DutOptions o;
  o.seed = 1 + g_inst.size();
  in->dut = in->u->desc->make(o);
  in->ad = std::make_unique<ru::tb::RegistryAdapter>(*in->u->spec, in->u->cfg);
  in->opt.test = "trax-cosim";
  in->opt.seed = o.seed;
  in->opt.stages = in->u->latency;
  in->opt.inject.latency_delta = g_latency_delta;
  in->opt.quiet = true;
  in->opt.report_cycle_base = kResetCycles;
  in->opt.item_context = [raw](int64_t item) { return item_context(*raw, item); };
  in->sb = std::make_unique<ru::tb::Scoreboard>(*in->dut, *in->ad, in->opt);
  for (uint64_t c = 0; c < kResetCycles; ++c) in->sb->reset(c, true);
  in->now = cycle;
  g_inst.push_back(std::move(in));
  g_by_key[key] = raw;
  return *raw;
}

// Simulates every busy instance up to (not including) cycle t; idle ones jump to t.
void advance_all(uint64_t t) {
  for (auto& p : g_inst) {
    Inst& in = *p;
    while (in.now < t && in.sb->busy()) step(in, in.now, nullptr, nullptr);
    if (in.now < t) in.now = t;
  }
}

bool read_exact(void* p, size_t n) {
  return std::fread(p, 1, n, stdin) == n;
}

// Maps the operand record's words (trax::unit_words) onto the registry's fields of the unit.
void map_words(UnitSel& u) {
  std::map<std::string, int> first, count;
  int w = 0;
  for (const ru::trax::UnitWords& x : ru::trax::unit_words(u.op)) {
    first[x.port] = w;
    count[x.port] = x.n;
    w += x.n;
  }
  if (w != ru::trax::unit_inputs(u.op) + ru::trax::unit_outputs(u.op))
    fail_line(std::string("trax::unit_words(") + op_label(u.op) + ") does not cover the operand record");
  for (const synth::PortDir dir : {synth::PortDir::In, synth::PortDir::Out}) {
    std::vector<int>& words = dir == synth::PortDir::In ? u.in_word : u.out_word;
    std::map<std::string, int> seen;
    for (const synth::Field& f : synth::fields_for(*u.spec, u.cfg, dir)) {
      auto it = first.find(f.port);
      if (it == first.end()) {
        if (dir == synth::PortDir::In) fail_line(u.rtl + ": the operand record has no word for input " + f.name);
        words.push_back(-1);
        continue;
      }
      ++seen[f.port];
      words.push_back(it->second + f.elem);
    }
    for (const auto& [port, n] : seen)
      if (n != count[port])
        fail_line(u.rtl + ": port " + port + " has " + std::to_string(n) + " elements in the registry, the operand record " +
                  std::to_string(count[port]));
  }
  for (const auto& [port, n] : count)
    if (std::find(u.in_word.begin(), u.in_word.end(), first[port]) == u.in_word.end() &&
        std::find(u.out_word.begin(), u.out_word.end(), first[port]) == u.out_word.end())
      fail_line(u.rtl + ": the operand record's port " + port + " is not a data port of the unit");
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
  UnitSel box, tri, noise;
  box.op = Op::Box;
  tri.op = Op::Tri;
  noise.op = Op::Noise;
  unit_spec("box", kv["box"], box);
  unit_spec("tri", kv["tri"], tri);
  unit_spec("noise", kv["noise"], noise);
  if (box.algo != "plain" && box.algo != "conservative") fail_line("unknown box mode " + box.algo);
  if (tri.algo != "robust" && tri.algo != "mt") fail_line("unknown tri algorithm " + tri.algo);
  if (noise.algo != "fixed-trunc" && noise.algo != "fixed")
    fail_line("chip.noise = " + noise.algo +
              " has no RTL (ru_noise_trunc implements noise = fixed-trunc, ru_noise noise = fixed)");
  // The configurations this chip needs: trax::cosim::companion_units, the one description that
  // `rayunits trax --cosim-build` builds from too (format, options, latency as Stages).
  ru::trax::Config chip;
  chip.format = kv["format"];
  chip.box = box.algo;
  chip.tri = tri.algo;
  chip.noise = noise.algo;
  chip.unit(ru::trax::Unit::Box).latency = box.latency;
  chip.unit(ru::trax::Unit::Tri).latency = tri.latency;
  chip.unit(ru::trax::Unit::Noise).latency = noise.latency;
  // --cosim-fp: the FP units, "fp_add=fp:L:S ..." (all five or none; fp_fma with chip.fma)
  chip.fma = kv.count("fp_fma") > 0;
  const auto fpu = cosim::chip_fp_units(chip);  // the client's list: header keys, units, ops
  const bool fp = kv.count(fpu.front().name) > 0;
  std::vector<UnitSel> fps(fp ? fpu.size() : 0);
  for (size_t i = 0; i < fps.size(); ++i) {
    fps[i].op = static_cast<Op>(fpu[i].op);
    unit_spec(fpu[i].name, kv[fpu[i].name], fps[i]);
    chip.unit(fpu[i].unit).latency = fps[i].latency;
  }
  std::vector<std::pair<const ru::synth::UnitSpec*, ru::synth::UnitConfig>> need;
  try {
    need = ru::trax::cosim::companion_units(chip, fp);
  } catch (const std::exception& e) {
    fail_line(e.what());
  }
  std::vector<std::pair<UnitSel*, int>> sels = {{&box, 0}, {&tri, 1}, {&noise, 2}};
  for (size_t i = 0; i < fps.size(); ++i) sels.push_back({&fps[i], 3 + static_cast<int>(i)});
  for (auto [sel, k] : sels) {
    const ru::synth::UnitSpec& spec = *need[k].first;
    const ru::synth::UnitConfig& c = need[k].second;
    std::map<std::string, int64_t> want(c.params.begin(), c.params.end());
    if (spec.uses_format) {
      want["ExpW"] = c.fmt.exp_bits;
      want["FracW"] = c.fmt.frac_bits;
      want["Subnormals"] = c.fmt.subnormals ? 1 : 0;
      want["Round"] = static_cast<int>(c.fmt.round);
    }
    want["Stages"] = c.stages;
    std::string what = spec.name + (spec.uses_format ? " " + c.fmt.name() : std::string());
    for (const auto& [n, v] : c.params) what += " " + n + "=" + std::to_string(v);
    std::string have;
    sel->desc = find(spec.name, want, have);
    if (!sel->desc)
      fail_line("no RTL build of " + what + " at latency (Stages) " + std::to_string(c.stages) +
                " in tb_trax_cosim (built: " + have + "; add it to RU_TRAX_COSIM_* in tb/trax/CMakeLists.txt, " +
                "or run with --cosim-build)");
    sel->rtl = sel->desc->full_name();
    try {
      sel->spec = &spec;
      sel->cfg = ru::tb::unit_config(*sel->desc);
    } catch (const std::exception& e) {
      fail_line(sel->rtl + ": " + e.what());
    }
    map_words(*sel);
  }
  g_units[Op::Box] = box;
  g_units[Op::Tri] = tri;
  g_units[Op::Noise] = noise;
  std::string fp_rtl;
  for (const UnitSel& u : fps) {
    g_units[u.op] = u;
    fp_rtl += ", " + u.rtl;
  }
  reply("OK RTL " + box.rtl + ", " + tri.rtl + ", " + noise.rtl + fp_rtl);
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
        if (p->sb->busy()) {
          reply("MISMATCH in cycle " + std::to_string(r.cycle) + ": a result of RTL " + p->u->rtl + " of TM " +
                std::to_string(p->tm) + ", unit slot " + std::to_string(p->slot) + " is due after the run's last cycle");
          return 1;
        }
      break;
    }
    if (r.cycle < last) fail_line("operations out of cycle order");
    last = r.cycle;
    const Op op = static_cast<Op>(r.op);
    if (!g_units.count(op)) fail_line(std::string("an operation of a unit without RTL in this run: ") + op_label(op));
    const int n = ru::trax::unit_inputs(op) + ru::trax::unit_outputs(op);
    if (r.nwords != n) fail_line("bad record length");
    words.resize(n);
    if (!read_exact(words.data(), sizeof(uint64_t) * n)) fail_line("truncated record");
    const UnitSel& u = g_units.at(op);
    if (r.slot >= u.slots) fail_line("unit slot out of range");
    advance_all(r.cycle);
    Inst& in = instance(op, r.tm, r.slot, r.cycle);
    if (in.now != r.cycle) fail_line("two operations in one cycle on one unit slot");
    step(in, r.cycle, &r, words.data());
  }
  std::map<Op, uint64_t> by_op;
  for (const auto& p : g_inst) by_op[p->u->op] += p->sb->stats().checked;
  std::ostringstream o;
  o << "DONE compared=" << compared() << " box=" << by_op[Op::Box] << " tri=" << by_op[Op::Tri]
    << " noise=" << by_op[Op::Noise];
  for (const cosim::FpUnit& u : cosim::fp_units())
    if (g_units.count(static_cast<Op>(u.op))) o << " " << u.name << "=" << by_op[static_cast<Op>(u.op)];
  o << " rtl_instances=" << g_inst.size() << " rtl_cycles=" << g_rtl_cycles;
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
