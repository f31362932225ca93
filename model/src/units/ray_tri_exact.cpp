// The exact (slow) path and the filter constants of ray_tri_exact (units/ray_tri_exact.hpp).
#include "rayunits/units/ray_tri_exact.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <cmath>

namespace ru::units::exact_detail {

double unit_roundoff(const ru::num::Format& f) {
  return std::ldexp(1.0, f.round == ru::num::Round::RNE ? -(f.frac_bits + 1) : -f.frac_bits);
}

int bound_exp(const ru::num::Format& f, int n) {
  // c = ((1+u)^n - 1) / (1-u)^n, evaluated with rationals (exact), then the smallest K with c <= 2^K.
  const mpq_class u(unit_roundoff(f));
  mpq_class up = 1, dn = 1;
  for (int i = 0; i < n; ++i) {
    up *= 1 + u;
    dn *= 1 - u;
  }
  const mpq_class c = (up - 1) / dn;
  int k = -200;
  mpq_class p;
  for (;; ++k) {
    mpz_class num = 1, den = 1;
    if (k >= 0)
      mpz_mul_2exp(num.get_mpz_t(), num.get_mpz_t(), static_cast<unsigned>(k));
    else
      mpz_mul_2exp(den.get_mpz_t(), den.get_mpz_t(), static_cast<unsigned>(-k));
    p = mpq_class(num, den);
    if (c <= p) return k;
  }
}

bool abs_greater_scaled(double v, double p, int k) {
  v = std::fabs(v);
  if (v == 0) return false;
  if (p == 0) return true;
  int ev, ep;
  const double mv = std::frexp(v, &ev), mp = std::frexp(p, &ep);
  const long e1 = ev, e2 = static_cast<long>(ep) + k;
  if (e1 != e2) return e1 > e2;
  return mv > mp;
}

namespace {
mpq_class q(double x) { return mpq_class(x); }  // exact (finite doubles only, checked by the caller)
int sgnq(const mpq_class& x) { return sgn(x); }
}  // namespace

int exact_edge_sign(const Vec3d& a, const Vec3d& d, const Vec3d& m, const Vec3d& q1, const Vec3d& q2,
                    bool vertex_order_tie) {
  const mpq_class sx = q(a.x) - q(m.x), sy = q(a.y) - q(m.y), sz = q(a.z) - q(m.z);
  const mpq_class dx = q(d.x), dy = q(d.y), dz = q(d.z);
  mpq_class ex = q(q1.x) - q(q2.x), ey = q(q1.y) - q(q2.y), ez = q(q1.z) - q(q2.z);
  // ((a - m) x d) . e
  const mpq_class S = (sy * dz - sz * dy) * ex + (sz * dx - sx * dz) * ey + (sx * dy - sy * dx) * ez;
  if (const int s = sgnq(S)) return s;
  int flip = 1;
  if (vertex_order_tie && !lex_first_is_min(q2, q1)) flip = -1;  // planted: orientation lexmin -> lexmax
  // (eps, eps^2, eps^3) . (d x e)
  const mpq_class gx = dy * ez - dz * ey, gy = dz * ex - dx * ez, gz = dx * ey - dy * ex;
  if (const int s = sgnq(gx)) return flip * s;
  if (const int s = sgnq(gy)) return flip * s;
  return flip * sgnq(gz);
}

bool exact_interval(const Vec3d& a, const Vec3d& d, const Vec3d& p0, const Vec3d& p1, const Vec3d& p2,
                    double t_min, double t_max) {
  if (std::isnan(t_min) || std::isnan(t_max)) return false;
  const mpq_class e1x = q(p2.x) - q(p0.x), e1y = q(p2.y) - q(p0.y), e1z = q(p2.z) - q(p0.z);
  const mpq_class e0x = q(p1.x) - q(p2.x), e0y = q(p1.y) - q(p2.y), e0z = q(p1.z) - q(p2.z);
  const mpq_class nx = e1y * e0z - e1z * e0y, ny = e1z * e0x - e1x * e0z, nz = e1x * e0y - e1y * e0x;
  const mpq_class V = nx * q(d.x) + ny * q(d.y) + nz * q(d.z);
  if (sgn(V) == 0) return false;
  const mpq_class Va = nx * (q(p2.x) - q(a.x)) + ny * (q(p2.y) - q(a.y)) + nz * (q(p2.z) - q(a.z));
  const mpq_class t = Va / V;
  const bool above = std::isinf(t_min) ? t_min < 0 : t > q(t_min);
  const bool below = std::isinf(t_max) ? t_max > 0 : t < q(t_max);
  return above && below;
}

int fast_interval(double t_fp, double V, double PV, int kV, double Va, double Pa, int ka, double u,
                  double minnorm, double t_min, double t_max) {
  if (!std::isfinite(t_fp) || !std::isfinite(V) || !std::isfinite(PV) || !std::isfinite(Va) ||
      !std::isfinite(Pa))
    return -1;
  if (std::isnan(t_min) || std::isnan(t_max)) return 0;
  if (!abs_greater_scaled(V, PV, kV)) return -1;  // V's sign (and a relative bound) certified
  // Absolute bounds BV >= |fl(V) - V|, Ba >= |fl(Va) - Va| (2^k P; ldexp is exact in the normal
  // double range, and a result below it is replaced by the larger 2^-1000).
  double BV = std::ldexp(PV, kV), Ba = std::ldexp(Pa, ka);
  if (PV != 0 && BV < 0x1p-1000) BV = 0x1p-1000;
  if (Pa != 0 && Ba < 0x1p-1000) Ba = 0x1p-1000;
  const double aV = std::fabs(V), at = std::fabs(t_fp);
  const double rhoV = BV / aV * (1 + 0x1p-40);
  if (!(rhoV < 0.5)) return -1;
  // With t_q = fl(Va)/fl(V) (exact quotient), t = Va/V:
  //   |t - t_q| = |(Va - fl(Va)) fl(V) - fl(Va) (V - fl(V))| / (|V| |fl(V)|)
  //            <= (Ba + |t_q| BV) / (|fl(V)| (1 - rhoV)),
  //   t_fp = t_q (1 + theta), |theta| <= u, so |t_q| <= |t_fp| / (1-u), |t_fp - t_q| <= u |t_fp| / (1-u),
  //   plus minnorm when the division result is below the normal range (its error is absolute).
  // The double evaluation below rounds up by the (1 + 2^-30) factor and the 2^-50 |t_fp| term.
  const double tq = at / (1 - u);
  double err = (Ba + tq * BV) / (aV * (1 - rhoV)) + u * tq;
  if (at < minnorm) err += minnorm;
  err = err * (1 + 0x1p-30) + 0x1p-50 * at;
  const double lo = t_fp - err, hi = t_fp + err;
  if (t_min < lo && hi < t_max) return 1;
  if (hi < t_min || t_max < lo) return 0;
  return -1;
}

bool certified(const ru::num::Format& f, uint64_t v, uint64_t p, int k) {
  const int fb = f.frac_bits, emax_field = (1 << f.exp_bits) - 1;
  const uint64_t fmask = (uint64_t{1} << fb) - 1;
  const int ev = static_cast<int>((v >> fb) & static_cast<uint64_t>(emax_field)),
            ep = static_cast<int>((p >> fb) & static_cast<uint64_t>(emax_field));
  if (ev == 0 || ev == emax_field) return false;                 // v zero, subnormal, INF or NaN
  if (ep == emax_field || (ep == 0 && (p & fmask) != 0)) return false;  // p subnormal, INF or NaN
  if (ep == 0) return true;                                      // p = 0, v normal
  const int de = ev - ep;                                        // |v| > 2^k |p|: exponents, then fractions
  if (de != k) return de > k;
  return (v & fmask) > (p & fmask);
}

int fast_interval_format(const ru::num::Format& f, uint64_t t, uint64_t V, uint64_t PV, int kV, uint64_t Va,
                         uint64_t Pa, int ka, uint64_t t_min, uint64_t t_max) {
  namespace n = ru::num;
  using n::Round;
  n::Format up = f, tz = f;
  up.round = Round::RUP;
  tz.round = Round::RTZ;
  auto val = [&](uint64_t x) { return n::to_double(f, x); };
  auto finite = [&](uint64_t x) { return std::isfinite(val(x)); };
  for (uint64_t x : {t, V, PV, Va, Pa})
    if (!finite(x)) return -1;
  if (std::isnan(val(t_min)) || std::isnan(val(t_max))) return 0;
  bool bad = false;  // an upper bound that underflowed or overflowed
  auto U = [&](n::Result r) {
    if (r.flags & (n::kUnderflow | n::kOverflow)) bad = true;
    return r.bits;
  };
  const double minnorm = n::to_double(f, f.min_normal());
  const uint64_t aV = n::abs(f, V), at = n::abs(f, t);
  const bool t_tiny = val(at) < minnorm;  // t zero or subnormal: the division's error is absolute
  auto S = [&](uint64_t x, int k) {  // scale2
    const n::Result r = scale2(f, x, k);
    if (r.flags) bad = true;
    return r.bits;
  };
  const int lu = f.round == Round::RNE ? -(f.frac_bits + 1) : -f.frac_bits;  // u = 2^lu
  const uint64_t BV = S(PV, kV), Ba = S(Pa, ka);
  const uint64_t twoBV = S(BV, 1);
  if (bad || !n::lt(f, twoBV, aV).bits) return -1;  // rho = BV / |V| < 1/2
  const uint64_t one2u = n::from_double(f, 1 + std::ldexp(2.0, lu)).bits;  // 1 + 2u (exact for M >= 1)
  const uint64_t tq = U(n::mul(up, at, one2u));
  const uint64_t x = S(U(n::add(up, Ba, U(n::mul(up, tq, BV)))), 1);
  // u tq |V|, or for a tiny t 2 minnorm |V| >= u tq |V| + minnorm |V| (tq <= 2 minnorm, u <= 1/2)
  const uint64_t z = t_tiny ? S(aV, f.emin() + 1) : S(U(n::mul(up, tq, aV)), lu);
  const uint64_t R = U(n::add(up, x, z));
  if (bad || !finite(R)) return -1;
  // side of one bound: +1 t above it, -1 below, 0 undecided (diff = t - bound)
  auto side = [&](uint64_t bound, bool lower) -> int {
    const double b = val(bound);
    if (std::isinf(b)) return (b < 0) == lower ? (lower ? 1 : -1) : (lower ? -1 : 1);
    const uint64_t D = lower ? n::sub(tz, t, bound).bits : n::sub(tz, bound, t).bits;
    const uint64_t M = n::mul(tz, n::abs(f, D), aV).bits;
    if (!n::lt(f, R, M).bits) return 0;
    const bool pos = val(D) > 0;  // lower: t > t_min; upper: t_max > t
    return lower ? (pos ? 1 : -1) : (pos ? -1 : 1);
  };
  const int lo = side(t_min, true), hi = side(t_max, false);  // lo +1: above t_min; hi -1: below t_max
  if (lo < 0 || hi > 0) return 0;
  if (lo > 0 && hi < 0) return 1;
  return -1;
}

ru::num::Result scale2(const ru::num::Format& f, uint64_t x, int k) {
  const int fb = f.frac_bits, emax_field = (1 << f.exp_bits) - 1;
  const uint64_t fmask = (uint64_t{1} << fb) - 1;
  const int e = static_cast<int>((x >> fb) & static_cast<uint64_t>(emax_field));
  if (e == 0 && (x & fmask) == 0) return {x, 0};                    // +-0
  const int e2 = e + k;
  if (e == 0 || e == emax_field || e2 < 1 || e2 >= emax_field) return {x, ru::num::kInvalid};  // gives up
  return {(x & ~(static_cast<uint64_t>(emax_field) << fb)) | (static_cast<uint64_t>(e2) << fb), 0};
}

}  // namespace ru::units::exact_detail
