// rayunits fp: evaluate one operation in a format, or a stream of them (--batch).
// The --batch line format is a stable interface for external checkers: docs/CLI.md.
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "cli_util.hpp"
#include "command.hpp"
#include "rayunits/num/format.hpp"

namespace ru::cli {
namespace {

using ru::num::Format;
using ru::num::FormatError;
using ru::num::Op;

std::string hex_bits(uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string flags_long(uint8_t fl) {
  if (!fl) return "- (none)";
  std::string s = ru::num::flags_letters(fl) + " (";
  const char* names[] = {"invalid", "divide-by-zero", "overflow", "underflow", "inexact"};
  const uint8_t bits[] = {ru::num::kInvalid, ru::num::kDivZero, ru::num::kOverflow,
                          ru::num::kUnderflow, ru::num::kInexact};
  bool first = true;
  for (int i = 0; i < 5; ++i) {
    if (!(fl & bits[i])) continue;
    s += (first ? "" : ", ") + std::string(names[i]);
    first = false;
  }
  return s + ")";
}

bool is_hex_text(const std::string& t) {
  return t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X') && t.find_first_of(".pP") == std::string::npos;
}

// ---------------------------------------------------------------- one operation, human output
int run_single(Format f, const std::string& op_text, const std::vector<std::string>& operands) {
  Op op = ru::num::parse_op(op_text);
  int arity = ru::num::op_arity(op);
  if (static_cast<int>(operands.size()) != arity)
    throw UsageError(std::string(ru::num::op_name(op)) + " takes " + std::to_string(arity) + " operand" +
                     (arity == 1 ? "" : "s") + ", got " + std::to_string(operands.size()));
  uint64_t v[3] = {0, 0, 0};
  Format fin = f;  // decimal operands are rounded into the format with RNE, whatever --round says
  fin.round = ru::num::Round::RNE;
  for (int i = 0; i < arity; ++i) v[i] = ru::num::parse_operand(fin, operands[i]);
  ru::num::Result r = ru::num::apply(f, op, v[0], v[1], v[2]);

  std::printf("format  %s, rounding %s, %s\n", f.name().c_str(), ru::num::round_name(f.round),
              f.subnormals ? "subnormals" : "flush-to-zero");
  const char* labels[] = {"a", "b", "c"};
  for (int i = 0; i < arity; ++i) {
    double d = ru::num::to_double(f, v[i]);
    bool exact = true;
    std::string dec = decimal(d, &exact);
    std::string note;
    if (!is_hex_text(operands[i])) {
      // Decimal input: say so when the text was rounded into the format.
      char* end = nullptr;
      double typed = std::strtod(operands[i].c_str(), &end);
      if (!(typed == d || (typed != typed && d != d))) note = "  (rounded from " + operands[i] + ")";
    } else if (!f.subnormals && d == 0 && (v[i] & ~f.sign_bit()) != 0) {
      note = "  (subnormal, reads as zero in a -ftz format)";
    }
    std::printf("%-7s %-18s %s%s%s\n", labels[i], hex_bits(v[i]).c_str(), dec.c_str(), exact ? "" : " (approx.)",
                note.c_str());
  }
  bool is_cmp = op == Op::Lt || op == Op::Le || op == Op::Eq;
  if (is_cmp) {
    std::printf("%-7s %-18s %s\n", ru::num::op_name(op), hex_bits(r.bits).c_str(), r.bits ? "true" : "false");
  } else {
    double d = ru::num::to_double(f, r.bits);
    bool exact = true;
    std::string dec = decimal(d, &exact);
    std::string hf = ru::num::is_nan(f, r.bits) || d - d != 0 ? "" : "  = " + hexfloat(d);
    std::printf("%-7s %-18s %s%s%s\n", ru::num::op_name(op), hex_bits(r.bits).c_str(), dec.c_str(),
                exact ? "" : " (approx.)", hf.c_str());
  }
  std::printf("%-7s %s\n", "flags", flags_long(r.flags).c_str());
  return 0;
}

// ---------------------------------------------------------------- --batch: stable, fast
class BatchError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

bool parse_hex_field(std::string_view t, const Format& f, uint64_t& out, std::string& why) {
  if (t.size() < 3 || t[0] != '0' || (t[1] != 'x' && t[1] != 'X')) {
    why = "operand '" + std::string(t) + "' is not a 0x bit pattern";
    return false;
  }
  uint64_t v = 0;
  size_t digits = 0;
  for (size_t i = 2; i < t.size(); ++i) {
    char c = t[i];
    unsigned d;
    if (c >= '0' && c <= '9') d = c - '0';
    else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
    else {
      why = "operand '" + std::string(t) + "' has a non-hex digit";
      return false;
    }
    if (v >> 60) {
      why = "operand '" + std::string(t) + "' does not fit " + f.name() + " (" + std::to_string(f.width()) + " bits)";
      return false;
    }
    v = v << 4 | d;
    ++digits;
  }
  if (v & ~f.mask()) {
    why = "operand '" + std::string(t) + "' does not fit " + f.name() + " (" + std::to_string(f.width()) + " bits)";
    return false;
  }
  out = v;
  return digits > 0;
}

class Batch {
 public:
  Batch() { out_.reserve(kFlushAt + 64); }
  ~Batch() { flush(); }

  // Processes one line (without '\n'). Throws BatchError with the reason on a malformed line.
  void line(std::string_view s) {
    std::string_view tok[8];
    int n = 0;
    size_t i = 0;
    while (i < s.size()) {
      while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
      if (i >= s.size()) break;
      size_t j = i;
      while (j < s.size() && s[j] != ' ' && s[j] != '\t' && s[j] != '\r') ++j;
      if (n == 0 && s[i] == '#') return;  // comment line
      if (n < 8) tok[n] = s.substr(i, j - i);
      ++n;
      i = j;
    }
    if (n == 0) return;  // blank line
    if (n < 4) throw BatchError("expected 'FORMAT OP A [B [C]] ROUND', got " + std::to_string(n) + " field" + (n == 1 ? "" : "s"));
    if (tok[0] != fmt_text_) {
      try {
        fmt_ = Format::parse(tok[0]);
      } catch (const FormatError& e) {
        fmt_text_.clear();
        throw BatchError(e.what());
      }
      fmt_text_ = std::string(tok[0]);
    }
    Op op;
    ru::num::Round rm;
    try {
      op = ru::num::parse_op(tok[1]);
      rm = ru::num::parse_round(tok[n - 1 < 8 ? n - 1 : 7]);
    } catch (const FormatError& e) {
      throw BatchError(e.what());
    }
    int arity = ru::num::op_arity(op);
    if (n != 3 + arity)
      throw BatchError(std::string(ru::num::op_name(op)) + " takes " + std::to_string(arity) + " operand" +
                       (arity == 1 ? "" : "s") + ": expected " + std::to_string(3 + arity) + " fields, got " +
                       std::to_string(n));
    uint64_t v[3] = {0, 0, 0};
    std::string why;
    for (int k = 0; k < arity; ++k)
      if (!parse_hex_field(tok[2 + k], fmt_, v[k], why)) throw BatchError(why);
    Format f = fmt_;
    f.round = rm;
    ru::num::Result r = ru::num::apply(f, op, v[0], v[1], v[2]);
    emit(r);
  }

  void flush() {
    if (!out_.empty()) std::fwrite(out_.data(), 1, out_.size(), stdout);
    out_.clear();
    std::fflush(stdout);
  }

 private:
  static constexpr size_t kFlushAt = 1 << 16;

  void emit(const ru::num::Result& r) {
    char buf[32];
    int p = 0;
    buf[p++] = '0';
    buf[p++] = 'x';
    int nib = 15;
    while (nib > 0 && ((r.bits >> (4 * nib)) & 15) == 0) --nib;
    for (; nib >= 0; --nib) buf[p++] = "0123456789abcdef"[(r.bits >> (4 * nib)) & 15];
    buf[p++] = ' ';
    if (!r.flags) buf[p++] = '-';
    if (r.flags & ru::num::kInvalid) buf[p++] = 'i';
    if (r.flags & ru::num::kDivZero) buf[p++] = 'z';
    if (r.flags & ru::num::kOverflow) buf[p++] = 'o';
    if (r.flags & ru::num::kUnderflow) buf[p++] = 'u';
    if (r.flags & ru::num::kInexact) buf[p++] = 'x';
    buf[p++] = '\n';
    out_.append(buf, p);
    if (out_.size() >= kFlushAt) {
      std::fwrite(out_.data(), 1, out_.size(), stdout);
      out_.clear();
    }
  }

  std::string out_;
  std::string fmt_text_;
  Format fmt_;
};

int run_batch() {
  Batch batch;
  std::vector<char> buf(1 << 20);
  std::string carry;  // an incomplete line from the previous read
  long line_no = 0;
  auto do_line = [&](std::string_view s) {
    ++line_no;
    try {
      batch.line(s);
    } catch (const BatchError& e) {
      batch.flush();  // every earlier line's result is out before the error
      std::string shown(s.substr(0, 120));
      throw UsageError("stdin line " + std::to_string(line_no) + ": " + e.what() + " (line: '" + shown +
                       (s.size() > 120 ? "...'" : "'") + ")");
    }
  };
  size_t got;
  while ((got = std::fread(buf.data(), 1, buf.size(), stdin)) > 0) {
    std::string_view chunk(buf.data(), got);
    size_t start = 0;
    while (true) {
      size_t nl = chunk.find('\n', start);
      if (nl == std::string_view::npos) break;
      if (!carry.empty()) {
        carry.append(chunk.substr(start, nl - start));
        do_line(carry);
        carry.clear();
      } else {
        do_line(chunk.substr(start, nl - start));
      }
      start = nl + 1;
    }
    carry.append(chunk.substr(start));
    if (carry.size() > (1u << 20)) throw UsageError("stdin line " + std::to_string(line_no + 1) + ": line too long");
  }
  if (std::ferror(stdin)) throw UsageError("error reading stdin");
  if (!carry.empty()) do_line(carry);  // last line without '\n'
  batch.flush();
  return 0;
}

// CLI11 would read "-1.5" as an option; numbers that start with '-' are moved behind "--".
std::vector<std::string> split_negative_numbers(int argc, char** argv, std::vector<std::string>& numbers) {
  std::vector<std::string> rest;
  bool after_dashdash = false;
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    const bool option_value = i > 0 && std::string(argv[i - 1]) == "--round";
    if (i > 0 && !after_dashdash && !option_value && a.size() > 1 && a[0] == '-' &&
        (std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.' || a == "-inf" || a == "-nan" ||
         a == "-infinity")) {
      numbers.push_back(a);
      rest.push_back("\x01");  // placeholder keeps the positional order
      continue;
    }
    if (a == "--") after_dashdash = true;
    rest.push_back(a);
  }
  return rest;
}

int run_fp(int argc, char** argv) {
  CLI::App app{
      "Evaluate one operation in a number format and print the result as decimal, hex bits and "
      "IEEE flags. Operands are decimal numbers (rounded into the format, RNE) or raw bit "
      "patterns 0x...\n"
      "  rayunits fp e7m16 mul 1.5 3.25 [--round rne|rtz|rdn|rup] [--ftz]\n"
      "  rayunits fp --batch < lines      (stable checker interface, see docs/CLI.md)",
      "rayunits fp"};
  std::string fmt_text, op_text, round_text = "rne";
  std::vector<std::string> operands;
  bool ftz = false, batch = false;
  app.add_option("format", fmt_text, "eXmY or eXmY-ftz");
  app.add_option("op", op_text, "add sub mul div sqrt fma min max lt le eq");
  app.add_option("operands", operands, "1 to 3 operands: decimal or 0x bit pattern");
  app.add_option("--round", round_text, "rounding of the operation: rne (default), rtz, rdn, rup");
  app.add_flag("--ftz", ftz, "flush-to-zero (same as the -ftz suffix)");
  app.add_flag("--batch", batch, "read 'FORMAT OP A [B [C]] ROUND' lines (0x operands) from stdin");

  // Negative numbers: replace them by placeholders, parse, then put them back in order.
  std::vector<std::string> negatives;
  std::vector<std::string> args = split_negative_numbers(argc, argv, negatives);
  std::vector<char*> av;
  for (auto& a : args) av.push_back(a.data());
  if (!parse_args(app, static_cast<int>(av.size()), av.data())) return 0;
  size_t next_neg = 0;
  for (auto* field : {&fmt_text, &op_text})
    if (*field == "\x01") *field = negatives[next_neg++];
  for (auto& o : operands)
    if (o == "\x01") o = negatives[next_neg++];

  if (batch) {
    if (!fmt_text.empty() || !operands.empty() || ftz || app.count("--round"))
      throw UsageError("--batch reads everything from stdin; it takes no format, operands, --round or --ftz");
    return run_batch();
  }
  if (fmt_text.empty() || op_text.empty())
    throw UsageError("expected FORMAT OP OPERANDS (e.g. 'rayunits fp e7m16 mul 1.5 3.25') or --batch");
  Format f = Format::parse(fmt_text);
  if (ftz) f.subnormals = false;
  // Operands are rounded into the format with RNE; --round applies to the operation.
  f.round = ru::num::parse_round(round_text);
  return run_single(f, op_text, operands);
}

}  // namespace

RU_COMMAND("fp", "evaluate one operation in a format (or --batch lines from stdin)", run_fp);

}  // namespace ru::cli
