// Enumeration of the equivalent scalar triple products (units/formulas.hpp).
#include "rayunits/units/formulas.hpp"

#include <array>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <tuple>

namespace ru::units {
namespace {

using I3 = std::array<long long, 3>;

I3 isub(const I3& a, const I3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
I3 icross(const I3& u, const I3& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}
long long idot(const I3& u, const I3& v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

// A generic integer configuration (no degeneracy) for deriving the exact sign of each
// formulation: the canonical volumes are non-zero here.
struct Config {
  I3 p[3], a, d;
};
const Config kConfigs[2] = {
    {{{3, -7, 2}, {-5, 4, 9}, {8, 6, -3}}, {1, 11, -13}, {-2, 5, 7}},
    {{{-4, 9, 1}, {6, -2, 5}, {2, 7, -8}}, {12, -3, 10}, {3, -6, 4}},
};

// Points of the volume for a configuration (and k for V_k).
std::vector<I3> points(VolKind kind, const Config& c, int k) {
  switch (kind) {
    case VolKind::V: return {c.p[0], c.p[1], c.p[2]};
    case VolKind::Va: return {c.p[0], c.p[1], c.p[2], c.a};
    default: return {c.a, c.p[(k + 1) % 3], c.p[(k + 2) % 3]};
  }
}

long long canonical(VolKind kind, const Config& c, int k) {
  const auto& p = c.p;
  switch (kind) {
    case VolKind::V: return idot(icross(isub(p[2], p[0]), isub(p[1], p[2])), c.d);
    case VolKind::Va: return idot(icross(isub(p[2], p[0]), isub(p[2], p[1])), isub(c.a, p[2]));
    default: {
      const I3& q1 = p[(k + 1) % 3];
      const I3& q2 = p[(k + 2) % 3];
      return idot(icross(isub(c.a, q2), c.d), isub(q1, q2));
    }
  }
}

I3 term_value(const StpTerm& t, const std::vector<I3>& pts, const Config& c) {
  return t.is_d() ? c.d : isub(pts[t.i], pts[t.j]);
}

int derive_sign(VolKind kind, const Stp& s) {
  int sign = 0;
  for (const Config& c : kConfigs) {
    for (int k = 0; k < (kind == VolKind::Vk ? 3 : 1); ++k) {
      const auto pts = points(kind, c, k);
      const long long want = canonical(kind, c, k);
      const long long got = idot(icross(term_value(s.u, pts, c), term_value(s.v, pts, c)), term_value(s.w, pts, c));
      int sg;
      if (want != 0 && got == want) {
        sg = 1;
      } else if (want != 0 && got == -want) {
        sg = -1;
      } else {
        throw std::logic_error("formulas: a scalar triple product is not an equivalent volume");
      }
      if (sign != 0 && sg != sign) throw std::logic_error("formulas: inconsistent sign");
      sign = sg;
    }
  }
  return sign;
}

struct Tables {
  std::vector<Stp> list;
  std::vector<Stp> reps;
  int classes = 0;
};

Tables build(VolKind kind) {
  Tables t;
  const int npts = kind == VolKind::Va ? 4 : 3;
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < npts; ++i)
    for (int j = i + 1; j < npts; ++j) edges.push_back({i, j});
  // Edge sets: V-type: pairs of edges (with d); Va: non-coplanar triples.
  std::vector<std::vector<int>> sets;
  const int ne = static_cast<int>(edges.size());
  if (kind != VolKind::Va) {
    for (int x = 0; x < ne; ++x)
      for (int y = x + 1; y < ne; ++y) sets.push_back({x, y});
  } else {
    for (int x = 0; x < ne; ++x)
      for (int y = x + 1; y < ne; ++y)
        for (int z = y + 1; z < ne; ++z) {
          int used = 0;
          for (int e : {x, y, z}) used |= (1 << edges[e].first) | (1 << edges[e].second);
          if (used == 0xF) sets.push_back({x, y, z});  // all four points: not one face
        }
  }
  for (const auto& set : sets) {
    // Vectors: -1 = d (V-type only), else edge index.
    std::vector<int> vecs;
    if (kind != VolKind::Va) vecs.push_back(-1);
    for (int e : set) vecs.push_back(e);
    const int n_dir_edges = static_cast<int>(set.size());
    for (int wi = 0; wi < 3; ++wi) {
      std::vector<int> cr;
      for (int q = 0; q < 3; ++q)
        if (q != wi) cr.push_back(vecs[q]);
      const int cls = t.classes++;
      for (int dirs = 0; dirs < (1 << n_dir_edges); ++dirs) {
        auto make = [&](int v) {
          StpTerm term;
          if (v < 0) return term;
          int bit = 0;
          for (int q = 0; q < n_dir_edges; ++q)
            if (set[q] == v) bit = q;
          const bool rev = (dirs >> bit) & 1;
          term.i = static_cast<int8_t>(rev ? edges[v].second : edges[v].first);
          term.j = static_cast<int8_t>(rev ? edges[v].first : edges[v].second);
          return term;
        };
        Stp s;
        s.u = make(cr[0]);
        s.v = make(cr[1]);
        s.w = make(vecs[wi]);
        s.cls = cls;
        s.sign = derive_sign(kind, s);
        t.list.push_back(s);
        if (dirs == 0) t.reps.push_back(s);
      }
    }
  }
  return t;
}

const Tables& tables(VolKind kind) {
  static const Tables t[3] = {build(VolKind::V), build(VolKind::Va), build(VolKind::Vk)};
  return t[static_cast<int>(kind)];
}

std::string point_name(VolKind kind, int idx, int k) {
  if (kind == VolKind::V) return "p" + std::to_string(idx);
  if (kind == VolKind::Va) return idx == 3 ? "a" : "p" + std::to_string(idx);
  if (idx == 0) return "a";
  if (k < 0) return idx == 1 ? "q1" : "q2";
  return "p" + std::to_string((k + idx) % 3);
}

std::string term_text(VolKind kind, const StpTerm& t, int k, bool paren) {
  if (t.is_d()) return "d";
  std::string s = point_name(kind, t.i, k) + " - " + point_name(kind, t.j, k);
  return paren ? "(" + s + ")" : s;
}

bool same(const StpTerm& a, const StpTerm& b) { return a.i == b.i && a.j == b.j; }

}  // namespace

const char* vol_kind_name(VolKind k) {
  switch (k) {
    case VolKind::V: return "V";
    case VolKind::Va: return "Va";
    default: return "V012";
  }
}

std::string Stp::text(VolKind kind, int k) const {
  std::string s = sign < 0 ? "-" : "";
  s += "[" + term_text(kind, u, k, true) + " x " + term_text(kind, v, k, true) + "] . " +
       term_text(kind, w, k, true);
  return s;
}

const std::vector<Stp>& stp_formulas(VolKind kind) { return tables(kind).list; }
int stp_class_count(VolKind kind) { return tables(kind).classes; }
const std::vector<Stp>& stp_class_reps(VolKind kind) { return tables(kind).reps; }

int find_stp(VolKind kind, StpTerm u, StpTerm v, StpTerm w) {
  const auto& l = stp_formulas(kind);
  for (size_t n = 0; n < l.size(); ++n) {
    const Stp& s = l[n];
    if (!same(s.w, w)) continue;
    if ((same(s.u, u) && same(s.v, v)) || (same(s.u, v) && same(s.v, u))) return static_cast<int>(n);
  }
  return -1;
}

namespace {
StpTerm T(int i, int j) {
  StpTerm t;
  t.i = static_cast<int8_t>(i);
  t.j = static_cast<int8_t>(j);
  return t;
}
const StpTerm D{};
}  // namespace

VolKind known_formula_kind(KnownFormula f) {
  switch (f) {
    case KnownFormula::Eq33:
    case KnownFormula::MtV: return VolKind::V;
    case KnownFormula::Eq34:
    case KnownFormula::MtVa: return VolKind::Va;
    default: return VolKind::Vk;
  }
}

int known_formula_class(KnownFormula f) {
  int n = -1;
  switch (f) {
    case KnownFormula::Eq33: n = find_stp(VolKind::V, T(2, 0), T(1, 2), D); break;
    case KnownFormula::Eq34: n = find_stp(VolKind::Va, T(2, 0), T(2, 1), T(3, 2)); break;
    case KnownFormula::Eq35: n = find_stp(VolKind::Vk, T(0, 2), D, T(1, 2)); break;
    case KnownFormula::Eq36: n = find_stp(VolKind::Vk, T(0, 1), D, T(1, 2)); break;
    case KnownFormula::MtV: n = find_stp(VolKind::V, D, T(2, 0), T(1, 0)); break;
    case KnownFormula::MtVa: n = find_stp(VolKind::Va, T(3, 0), T(1, 0), T(2, 0)); break;
  }
  if (n < 0) throw std::logic_error("formulas: known formula not found");
  return stp_formulas(known_formula_kind(f))[n].cls;
}

const char* known_formula_name(KnownFormula f) {
  switch (f) {
    case KnownFormula::Eq33: return "Eq. 3.3";
    case KnownFormula::Eq34: return "Eq. 3.4";
    case KnownFormula::Eq35: return "Eq. 3.5";
    case KnownFormula::Eq36: return "Eq. 3.6";
    case KnownFormula::MtV: return "Eq. 3.2 (MT) V";
    default: return "Eq. 3.2 (MT) Va";
  }
}

}  // namespace ru::units
