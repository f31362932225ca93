// Today's ray-triangle units in the datapath IR (see rayunits/dp/formulas.hpp).
#include "rayunits/dp/formulas.hpp"

#include <algorithm>
#include <map>

namespace ru::dp {

namespace {

struct V3 {
  int x, y, z;
};

// Mixed precision (TriGenome::wide): where values move into the graph's wide format and back. A
// value is converted once (a cvt node per value and direction, shared by its users); with mode 0
// nothing is converted and the graphs are node for node those before the gene existed.
struct Prec {
  Graph* g = nullptr;
  int mode = 0;  // TriGenome::wide
  std::map<int, int> up_, down_;
  int up(int x) {
    if (g->nodes()[x].wide) return x;
    const auto it = up_.find(x);
    return it != up_.end() ? it->second : up_[x] = g->cvt(x);
  }
  int down(int x) {
    if (!g->nodes()[x].wide || op_is_bool(g->nodes()[x].op)) return x;
    const auto it = down_.find(x);
    return it != down_.end() ? it->second : down_[x] = g->cvt(x);
  }
  V3 up(V3 v) {
    const int x = up(v.x), y = up(v.y);
    return {x, y, up(v.z)};
  }
};

// The vec.hpp operation orders (docs/UNITS.md "Dataflow").
V3 vsub(Graph& g, V3 u, V3 v) { return {g.sub(u.x, v.x), g.sub(u.y, v.y), g.sub(u.z, v.z)}; }
// u x v; fused (TriGenome::fuse 2): each component as one fma on the second product's negation,
// u_y v_z - u_z v_y = fma(u_y, v_z, -(u_z v_y)) (one rounding of the difference and the first product).
// Mixed precision 2 (P->mode): the operands converted up, the product stays wide.
V3 cross(Graph& g, V3 u, V3 v, bool fused = false, Prec* P = nullptr) {
  if (P && P->mode == 2) u = P->up(u), v = P->up(v);
  auto comp = [&](int a, int b, int c, int d) {  // a b - c d
    if (fused) return g.fma(a, b, g.neg(g.mul(c, d)));
    return g.sub(g.mul(a, b), g.mul(c, d));
  };
  const int x = comp(u.y, v.z, u.z, v.y);
  const int y = comp(u.z, v.x, u.x, v.z);
  const int z = comp(u.x, v.y, u.y, v.x);
  return {x, y, z};
}
// dot(u, v) in one of three associations (TriGenome::dot); 0 is vec.hpp's (xx + yy) + zz.
// (Node order of association 0: yy, xx, xx + yy, zz, sum — the order the checked-in emitted RTL
// has, rtl/ru_dp_*.sv.) Fused (TriGenome::fuse >= 1): the same association as a chain of fmas on
// the one product that is added first: (xx + yy) + zz = fma(z, z', fma(x, x', yy)),
// xx + (yy + zz) = fma(x, x', fma(y, y', zz)), (xx + zz) + yy = fma(y, y', fma(x, x', zz)).
// Mixed precision 1 and 2 (P->mode): computed in the wide format from operands converted up, the
// result rounded back; 3: everything is wide already, the result stays wide.
int dot_in(Graph& g, V3 u, V3 v, int assoc, bool fused);
int dot(Graph& g, V3 u, V3 v, int assoc = 0, bool fused = false, Prec* P = nullptr) {
  if (!P || P->mode == 0 || P->mode == 3) return dot_in(g, u, v, assoc, fused);
  u = P->up(u), v = P->up(v);
  return P->down(dot_in(g, u, v, assoc, fused));
}
int dot_in(Graph& g, V3 u, V3 v, int assoc, bool fused) {
  if (fused) {
    if (assoc == 1) return g.fma(u.x, v.x, g.fma(u.y, v.y, g.mul(u.z, v.z)));
    if (assoc == 2) return g.fma(u.y, v.y, g.fma(u.x, v.x, g.mul(u.z, v.z)));
    return g.fma(u.z, v.z, g.fma(u.x, v.x, g.mul(u.y, v.y)));
  }
  if (assoc == 1) {
    const int xx = g.mul(u.x, v.x), yy = g.mul(u.y, v.y), zz = g.mul(u.z, v.z);
    return g.add(xx, g.add(yy, zz));
  }
  if (assoc == 2) {
    const int xx = g.mul(u.x, v.x), zz = g.mul(u.z, v.z);
    const int xz = g.add(xx, zz);
    return g.add(xz, g.mul(u.y, v.y));
  }
  const int yy = g.mul(u.y, v.y);
  const int xx = g.mul(u.x, v.x);
  const int xy = g.add(xx, yy);
  const int zz = g.mul(u.z, v.z);
  return g.add(xy, zz);
}
// units::lex_first_is_min(l, r): l unless r is lexicographically smaller (x, then y, then z).
int lex_first_is_min(Graph& g, V3 l, V3 r) {
  const int z = g.lor(g.lt(l.z, r.z), g.lnot(g.gt(l.z, r.z)));
  const int y = g.lor(g.lt(l.y, r.y), g.land(g.lnot(g.gt(l.y, r.y)), z));
  return g.lor(g.lt(l.x, r.x), g.land(g.lnot(g.gt(l.x, r.x)), y));
}
V3 select(Graph& g, int p, V3 a, V3 b) { return {g.select(p, a.x, b.x), g.select(p, a.y, b.y), g.select(p, a.z, b.z)}; }

struct TriInputs {
  V3 a, d, p0, p1, p2;
  int tmin, tmax;
};
TriInputs tri_inputs(Graph& g) {
  auto vec = [&](const char* n) {
    const std::string s = n;
    const int x = g.input(s + "x");
    const int y = g.input(s + "y");
    return V3{x, y, g.input(s + "z")};
  };
  TriInputs t;
  t.a = vec("a");
  t.d = vec("d");
  t.p0 = vec("p0");
  t.p1 = vec("p1");
  t.p2 = vec("p2");
  t.tmin = g.input("tmin");
  t.tmax = g.input("tmax");
  return t;
}

// The common tail of the triangle graphs: hit = accept & in_range, and the outputs in the order
// every triangle design has them (V0 only when the design computes it, v0 >= 0).
void tri_outputs(Graph& g, Prec& P, int accept, int in_range, int t, int beta, int gamma, int V, int Va, int v0,
                 int V1, int V2) {
  // outputs in the unit's format (mixed precision 3: each rounded back once)
  for (int* x : {&t, &beta, &gamma, &V, &Va, &v0, &V1, &V2})
    if (*x >= 0) *x = P.down(*x);
  g.output("hit", g.land(accept, in_range));
  g.output("t", t);
  g.output("beta", beta);
  g.output("gamma", gamma);
  g.output("V", V);
  g.output("Va", Va);
  if (v0 >= 0) g.output("V0", v0);
  g.output("V1", V1);
  g.output("V2", V2);
}

// t_min < t < t_max: on the quotient (interval 0), or on Va against t_min V and t_max V with the
// sides chosen by the sign of V (interval 1; V = 0 or NaN products: no hit).
int in_range(Graph& g, const TriInputs& in, int interval, int t, int V, int Va, int zero) {
  if (interval == 0) return g.land(g.lt(in.tmin, t), g.lt(t, in.tmax));
  const int lo = g.mul(in.tmin, V), hi = g.mul(in.tmax, V);
  const int pos = g.gt(V, zero);
  const int r_pos = g.land(g.lt(lo, Va), g.lt(Va, hi));
  const int r_neg = g.land(g.lt(hi, Va), g.lt(Va, lo));
  return g.lor(g.land(pos, r_pos), g.land(g.lnot(pos), r_neg));
}

// Three quotients n_k / V: three divisions, or one reciprocal 1/V (one: the constant 1's node, or
// -1 to make it here) and three products, in the order given.
std::array<int, 3> divide(Graph& g, int how, int V, std::array<int, 3> num, int one = -1) {
  std::array<int, 3> q{};
  if (how == 1) {
    const int inv = g.div(one >= 0 ? one : g.constant(1.0, g.nodes()[V].wide), V);
    for (int k = 0; k < 3; ++k) q[k] = g.mul(num[k], inv);
  } else {
    for (int k = 0; k < 3; ++k) q[k] = g.div(num[k], V);
  }
  return q;
}

// The graph of a genome starts here: the wide format when the genome has mixed precision, the
// inputs, and (mixed precision 3) every input converted up.
Graph start_graph(const TriGenome& G, TriInputs& in) {
  Graph g;
  if (G.wide) {
    if (G.wide_de <= 0 && G.wide_dm <= 0)
      throw IrError("genome " + genome_name(G) + ": mixed precision needs the wide format (rayunits search tri --mixed)");
    g.set_wide(G.wide_de, G.wide_dm);
  }
  in = tri_inputs(g);
  return g;
}
void start_prec(Graph& g, const TriGenome& G, TriInputs& in, Prec& P) {
  P.g = &g;
  P.mode = G.wide;
  if (G.wide == 3) {
    for (V3* v : {&in.a, &in.d, &in.p0, &in.p1, &in.p2}) *v = P.up(*v);
    in.tmin = P.up(in.tmin);
    in.tmax = P.up(in.tmax);
  }
}

Graph signed_volume_graph(const TriGenome& G) {
  TriInputs in;
  Prec P;
  Graph g = start_graph(G, in);
  start_prec(g, G, in, P);
  const V3 p[3] = {in.p0, in.p1, in.p2};
  // edge i runs from p_j to p_k, (j, k) = (1, 2), (2, 0), (0, 1): e_i = p_j - p_k as in Fig. 3.6
  // (e0 = p1 - p2), the edge opposite p_i
  const int J[3] = {1, 2, 0}, K[3] = {2, 0, 1};
  // The normal's edge pair (b x a) of denom 0..2; denom 3 uses the pair of 0 for Va.
  static const int kPair[3][2] = {{1, 0}, {2, 1}, {0, 2}};
  const int npair = G.denom == 3 ? 0 : G.denom;
  const bool need_normal = G.denom < 3 || G.va < 3;
  bool need_edge[3] = {G.edge_form < 3, G.edge_form < 3, G.edge_form < 3};
  if (need_normal) need_edge[kPair[npair][0]] = need_edge[kPair[npair][1]] = true;
  V3 e[3]{};
  for (int i = 0; i < 3; ++i)
    if (need_edge[i]) e[i] = vsub(g, p[J[i]], p[K[i]]);
  int s[3] = {-1, -1, -1};
  if ((G.edge_form < 3 && G.origin == 0) || G.tie)
    for (int i = 0; i < 3; ++i) s[i] = lex_first_is_min(g, p[J[i]], p[K[i]]);
  int Vi[3];
  V3 pa[3]{};  // p_j - a, made when first needed
  bool have_pa[3] = {false, false, false};
  auto p_minus_a = [&](int j) {
    if (!have_pa[j]) pa[j] = vsub(g, p[j], in.a), have_pa[j] = true;
    return pa[j];
  };
  if (G.edge_form < 3) {
    // a - m_i as in the RTL: the three differences a - p_j, then (origin 0) a selection
    const V3 ap[3] = {vsub(g, in.a, in.p0), vsub(g, in.a, in.p1), vsub(g, in.a, in.p2)};
    V3 am[3];
    for (int i = 0; i < 3; ++i)
      am[i] = G.origin == 0 ? select(g, s[i], ap[J[i]], ap[K[i]]) : G.origin == 1 ? ap[J[i]] : ap[K[i]];
    for (int i = 0; i < 3; ++i) {
      if (G.edge_form == 0) Vi[i] = dot(g, cross(g, am[i], in.d, G.fuse >= 2, &P), e[i], G.dot, G.fuse >= 1, &P);
      else if (G.edge_form == 1) Vi[i] = dot(g, cross(g, in.d, e[i], G.fuse >= 2, &P), am[i], G.dot, G.fuse >= 1, &P);
      else Vi[i] = dot(g, cross(g, e[i], am[i], G.fuse >= 2, &P), in.d, G.dot, G.fuse >= 1, &P);
    }
  } else {
    for (int j = 0; j < 3; ++j) p_minus_a(j);
    for (int i = 0; i < 3; ++i)
      Vi[i] = dot(g, cross(g, pa[K[i]], pa[J[i]], G.fuse >= 2, &P), in.d, G.dot, G.fuse >= 1, &P);
  }
  V3 N{};
  if (need_normal) N = cross(g, e[kPair[npair][0]], e[kPair[npair][1]], G.fuse >= 2, &P);
  const int V = G.denom < 3 ? dot(g, N, in.d, G.dot, G.fuse >= 1, &P) : g.add(g.add(Vi[0], Vi[1]), Vi[2]);
  // Va = N . (p_k - a) for any vertex k, or the triple product (u1 x u0) . u2 of u_k = p_k - a
  static const int kVaVertex[3] = {2, 0, 1};
  const int Va = G.va < 3 ? dot(g, N, p_minus_a(kVaVertex[G.va]), G.dot, G.fuse >= 1, &P)
                          : dot(g, cross(g, p_minus_a(1), p_minus_a(0), G.fuse >= 2, &P), p_minus_a(2), G.dot,
                                G.fuse >= 1, &P);
  const auto [t, beta, gamma] = divide(g, G.divide, V, {Va, Vi[1], Vi[2]});
  const int zero = g.constant(0.0, G.wide == 3);
  const int any_neg = g.lor(g.lor(g.lt(Vi[0], zero), g.lt(Vi[1], zero)), g.lt(Vi[2], zero));
  const int any_pos = g.lor(g.lor(g.gt(Vi[0], zero), g.gt(Vi[1], zero)), g.gt(Vi[2], zero));
  int ok = g.lnot(g.land(any_neg, any_pos));
  if (G.tie) {
    const int tie = g.lor(g.lor(g.land(g.eq(Vi[0], zero), s[0]), g.land(g.eq(Vi[1], zero), s[1])),
                          g.land(g.eq(Vi[2], zero), s[2]));
    ok = g.land(ok, g.lnot(tie));
  }
  const int range = in_range(g, in, G.interval, t, V, Va, zero);
  tri_outputs(g, P, ok, range, t, beta, gamma, V, Va, Vi[0], Vi[1], Vi[2]);
  return g;
}

Graph mt_graph(const TriGenome& G) {
  TriInputs in;
  Prec P;
  Graph g = start_graph(G, in);
  start_prec(g, G, in, P);
  const V3 e1 = vsub(g, in.p1, in.p0);
  const V3 e2 = vsub(g, in.p2, in.p0);
  const V3 s = vsub(g, in.a, in.p0);
  const V3 q = cross(g, in.d, e2, G.fuse >= 2, &P);
  const V3 r = cross(g, s, e1, G.fuse >= 2, &P);
  const int V = dot(g, q, e1, G.dot, G.fuse >= 1, &P);
  const int V1 = dot(g, q, s, G.dot, G.fuse >= 1, &P);
  const int V2 = dot(g, r, in.d, G.dot, G.fuse >= 1, &P);
  const int Va = dot(g, r, e2, G.dot, G.fuse >= 1, &P);
  const int one = g.constant(1.0, G.wide == 3);
  const auto [beta, gamma, t] = divide(g, G.divide, V, {V1, V2, Va}, one);
  const int sum = g.add(beta, gamma);
  const int zero = g.constant(0.0, G.wide == 3);
  const int inside = g.land(g.land(g.ge(beta, zero), g.ge(gamma, zero)), g.le(sum, one));
  const int range = in_range(g, in, G.interval, t, V, Va, zero);
  tri_outputs(g, P, inside, range, t, beta, gamma, V, Va, -1, V1, V2);
  return g;
}

}  // namespace

const std::array<const char*, kTriGenes>& tri_gene_names() {
  static const std::array<const char*, kTriGenes> n = {"family", "edge_form", "origin", "denom", "va",   "divide",
                                                       "interval", "tie",     "dot",    "fuse",  "wide"};
  return n;
}

std::vector<int> to_vector(const TriGenome& g) {
  return {g.family, g.edge_form, g.origin, g.denom, g.va, g.divide, g.interval, g.tie, g.dot, g.fuse, g.wide};
}

std::vector<int> genes_record(const TriGenome& g) {
  std::vector<int> v = to_vector(g);
  if (g.wide == 0) v.resize(kTriGenes - 1);
  if (g.wide == 0 && g.fuse == 0) v.resize(kTriGenesUnfused);
  return v;
}

TriGenome tri_genome(const std::vector<int>& v0) {
  std::vector<int> v = v0;
  if (v.size() == kTriGenesUnfused) v.push_back(0);  // written before the fuse gene
  if (v.size() == kTriGenes - 1) v.push_back(0);     // written before the wide gene, or wide 0
  if (v.size() != kTriGenes)
    throw IrError("a ray-triangle genome has " + std::to_string(kTriGenes) + " genes, got " + std::to_string(v.size()));
  for (int i = 0; i < kTriGenes; ++i)
    if (v[i] < 0 || v[i] >= kTriGeneCount[i])
      throw IrError(std::string("gene ") + tri_gene_names()[i] + " must be 0.." + std::to_string(kTriGeneCount[i] - 1) +
                    ", got " + std::to_string(v[i]));
  TriGenome g;
  g.family = v[0], g.edge_form = v[1], g.origin = v[2], g.denom = v[3], g.va = v[4], g.divide = v[5];
  g.interval = v[6], g.tie = v[7], g.dot = v[8], g.fuse = v[9], g.wide = v[10];
  return g;
}

TriGenome canonical(const TriGenome& g) {
  TriGenome c = g;
  if (c.family == 1) {
    c.edge_form = c.origin = c.denom = c.va = c.tie = 0;
  } else if (c.edge_form == 3) {
    c.origin = 0;  // form 3 has no origin
  }
  return c;
}

std::string genome_name(const TriGenome& g0) {
  const TriGenome g = canonical(g0);
  auto n = [](char c, int v) { return std::string("-") + c + std::to_string(v); };
  const std::string u = (g.fuse ? n('u', g.fuse) : "") + (g.wide ? n('w', g.wide) : "");
  if (g.family == 1) return "mt" + n('q', g.divide) + n('i', g.interval) + n('p', g.dot) + u;
  return "sv" + n('f', g.edge_form) + n('o', g.origin) + n('d', g.denom) + n('a', g.va) + n('q', g.divide) +
         n('i', g.interval) + n('t', g.tie) + n('p', g.dot) + u;
}

TriGenome parse_genome_name(const std::string& s) {
  const std::string form =
      "'sv-f<0-3>-o<0-2>-d<0-3>-a<0-3>-q<0-1>-i<0-1>-t<0-1>-p<0-2>[-u<1-2>][-w<1-3>]' or "
      "'mt-q<0-1>-i<0-1>-p<0-2>[-u<1-2>][-w<1-3>]'";
  auto bad = [&] { return IrError("bad genome name '" + s + "' (accepted: " + form + ")"); };
  std::vector<std::string> parts;
  size_t i = 0;
  while (i <= s.size()) {
    const size_t j = std::min(s.find('-', i), s.size());
    parts.push_back(s.substr(i, j - i));
    i = j + 1;
  }
  const bool mt = parts[0] == "mt";
  if (!mt && parts[0] != "sv") throw bad();
  std::string letters = mt ? "qip" : "foda" "qitp";
  // the fuse and wide genes, each written only when not 0
  for (const char opt : {'u', 'w'})
    if (parts.size() > letters.size() + 1 && !parts[letters.size() + 1].empty() && parts[letters.size() + 1][0] == opt)
      letters += opt;
  if (parts.size() != letters.size() + 1) throw bad();
  std::map<char, int> v;
  for (size_t k = 0; k < letters.size(); ++k) {
    const std::string& p = parts[k + 1];
    if (p.size() != 2 || p[0] != letters[k] || p[1] < '0' || p[1] > '9') throw bad();
    v[p[0]] = p[1] - '0';
  }
  if ((v.count('u') && v['u'] == 0) || (v.count('w') && v['w'] == 0)) throw bad();  // one name per genome: no "-u0"
  try {
    return tri_genome({mt ? 1 : 0, v['f'], v['o'], v['d'], v['a'], v['q'], v['i'], v['t'], v['p'], v['u'], v['w']});
  } catch (const IrError&) {
    throw bad();
  }
}

TriGenome fig36_genome() { return TriGenome{}; }
TriGenome mt_genome() {
  TriGenome g;
  g.family = 1;
  g.divide = 1;
  return g;
}

TriGenome start_genome(const std::string& name) {
  TriGenome g;
  if (name == "fig36") return g;
  if (name == "fig36_tie") return g.tie = 1, g;
  if (name == "fig36_recip") return g.divide = 1, g;
  if (name == "mt") return mt_genome();
  if (name == "worst") {
    g.origin = 1;
    g.va = 3;
    g.interval = 1;
    g.tie = 1;
    g.dot = 1;
    return g;
  }
  if (name.rfind("sv-", 0) == 0 || name.rfind("mt-", 0) == 0) return parse_genome_name(name);
  throw IrError("unknown start '" + name + "' (accepted: fig36, fig36_tie, fig36_recip, mt, worst, or a genome name "
                "such as sv-f0-o0-d0-a0-q0-i0-t0-p0)");
}

Graph tri_graph(const TriGenome& g0) {
  TriGenome g = canonical(tri_genome(to_vector(g0)));  // genes in range
  g.wide_de = g0.wide_de, g.wide_dm = g0.wide_dm;
  return g.family == 1 ? mt_graph(g) : signed_volume_graph(g);
}

Graph ray_tri_robust_graph(bool tie_break, bool reciprocal) {
  TriGenome g = fig36_genome();
  g.tie = tie_break;
  g.divide = reciprocal;
  return tri_graph(g);
}

Graph ray_tri_mt_graph() { return tri_graph(mt_genome()); }

const std::vector<Design>& designs() {
  TriGenome tie = fig36_genome(), recip = fig36_genome();
  tie.tie = 1;
  recip.divide = 1;
  static const std::vector<Design> d = {
      {"ray_tri_robust", "Kensler Fig. 3.6 (units::ray_tri_robust, no tie-break)", [] { return ray_tri_robust_graph(); },
       genome_name(fig36_genome())},
      {"ray_tri_robust_tie", "Fig. 3.6 with its zero-volume tie-break", [] { return ray_tri_robust_graph(true); },
       genome_name(tie)},
      {"ray_tri_robust_recip", "Fig. 3.6, one reciprocal 1/V and three multiplications",
       [] { return ray_tri_robust_graph(false, true); }, genome_name(recip)},
      {"ray_tri_mt", "Moller-Trumbore, Eq. 3.2 (units::ray_tri_mt)", [] { return ray_tri_mt_graph(); },
       genome_name(mt_genome())},
  };
  return d;
}

const Design& find_design(const std::string& name) {
  std::string known;
  for (const auto& d : designs()) {
    if (d.name == name) return d;
    known += (known.empty() ? "" : ", ") + d.name;
  }
  throw IrError("unknown design '" + name + "' (designs: " + known + ")");
}

// ---- ray-box formulations ---------------------------------------------------------------------

std::string box_genome_name(const BoxGenome& g) {
  return "box-r" + std::to_string(g.round) + "-f" + std::to_string(g.form) + "-m" + std::to_string(g.tree);
}

BoxGenome parse_box_genome_name(const std::string& s) {
  for (const BoxGenome& g : all_box_genomes())
    if (box_genome_name(g) == s) return g;
  throw IrError("bad ray-box genome name '" + s + "' (accepted: 'box-r<0-3>-f<0-1>-m<0-1>')");
}

std::vector<BoxGenome> all_box_genomes() {
  std::vector<BoxGenome> v;
  for (int r = 0; r < kBoxGeneCount[0]; ++r)
    for (int f = 0; f < kBoxGeneCount[1]; ++f)
      for (int m = 0; m < kBoxGeneCount[2]; ++m) v.push_back(BoxGenome{r, f, m});
  return v;
}

BoxGenome box_plain_genome() { return BoxGenome{}; }
BoxGenome box_conservative_genome() { return BoxGenome{1, 0, 0}; }

Graph box_graph(const BoxGenome& G) {
  if (G.round < 0 || G.round >= kBoxGeneCount[0] || G.form < 0 || G.form >= kBoxGeneCount[1] || G.tree < 0 ||
      G.tree >= kBoxGeneCount[2])
    throw IrError("box_graph: gene out of range in " + box_genome_name(G));
  using num::Round;
  Graph g;
  auto vec = [&](const char* n) {
    const std::string s = n;
    const int x = g.input(s + "x");
    const int y = g.input(s + "y");
    return V3{x, y, g.input(s + "z")};
  };
  const V3 o = vec("o"), inv = vec("i");
  const int tmin = g.input("tmin"), tmax = g.input("tmax");
  const V3 lo = vec("lo"), hi = vec("hi");
  const bool dir_diff = G.round == 1 || G.round == 3, dir_prod = G.round == 1 || G.round == 2;
  int tn[3], tf[3];
  for (int k = 0; k < 3; ++k) {
    auto c = [k](const V3& v) { return k == 0 ? v.x : k == 1 ? v.y : v.z; };
    const int neg = g.signbit(c(inv));
    // (one builder call per statement: the node order, and so the graph text, is fixed)
    const int near = g.select(neg, c(hi), c(lo));
    const int far = g.select(neg, c(lo), c(hi));
    if (G.form == 0) {
      int dn, df;
      if (dir_diff) {
        // RDN(near - o) for inv >= 0; for inv < 0 RUP(near - o) = -RDN(o - near): one subtracter,
        // operands swapped by the sign (as ru_ray_box does); the far side the same with RUP
        const int xn = g.select(neg, c(o), c(lo));
        const int yn = g.select(neg, c(hi), c(o));
        const int rn = g.rounded(g.sub(xn, yn), Round::RDN);
        const int nn = g.neg(rn);
        dn = g.select(neg, nn, rn);
        const int xf = g.select(neg, c(o), c(hi));
        const int yf = g.select(neg, c(lo), c(o));
        const int rf = g.rounded(g.sub(xf, yf), Round::RUP);
        const int nf = g.neg(rf);
        df = g.select(neg, nf, rf);
      } else {
        dn = g.sub(near, c(o));
        df = g.sub(far, c(o));
      }
      tn[k] = g.mul(dn, c(inv));
      tf[k] = g.mul(df, c(inv));
    } else {
      int pu, pd;
      if (dir_diff) {
        pu = g.rounded(g.mul(c(o), c(inv)), Round::RUP);  // >= o inv: tn below the exact value
        pd = g.rounded(g.mul(c(o), c(inv)), Round::RDN);
      } else {
        pu = pd = g.mul(c(o), c(inv));
      }
      const int mu = g.neg(pu);
      tn[k] = g.fma(near, c(inv), mu);
      const int md = pd == pu ? mu : g.neg(pd);
      tf[k] = g.fma(far, c(inv), md);
    }
    if (dir_prod) {
      g.rounded(tn[k], Round::RDN);
      g.rounded(tf[k], Round::RUP);
    }
  }
  int te, tx;
  if (G.tree == 0) {
    const int a = g.max(tn[0], tn[1]);
    const int b = g.max(tn[2], tmin);
    te = g.max(a, b);
    const int c = g.min(tf[0], tf[1]);
    const int d = g.min(tf[2], tmax);
    tx = g.min(c, d);
  } else {
    te = g.max(g.max(g.max(tmin, tn[0]), tn[1]), tn[2]);
    tx = g.min(g.min(g.min(tmax, tf[0]), tf[1]), tf[2]);
  }
  int any_nan = -1;
  for (int n = 0; n < 14; ++n) {
    const int x = g.isnan(n);  // inputs are nodes 0..13
    any_nan = any_nan < 0 ? x : g.lor(any_nan, x);
  }
  const int te_inf = g.isinf(te);
  const int te_pinf = g.land(te_inf, g.lnot(g.signbit(te)));
  const int tx_inf = g.isinf(tx);
  const int tx_ninf = g.land(tx_inf, g.signbit(tx));
  const int order = g.le(te, tx);
  const int no_inf = g.lnot(g.lor(te_pinf, tx_ninf));
  const int hit = g.land(g.land(order, no_inf), g.lnot(any_nan));
  g.output("hit", hit);
  g.output("t_enter", te);
  g.output("t_exit", tx);
  return g;
}

std::vector<double> box_inputs(const units::BoxRecord& r) {
  return {r.o.x,  r.o.y,  r.o.z,  r.inv.x, r.inv.y, r.inv.z, r.t_min,
          r.t_max, r.lo.x, r.lo.y, r.lo.z,  r.hi.x,  r.hi.y,  r.hi.z};
}

std::vector<double> tri_inputs(const units::TriRecord& r) {
  return {r.a.x,  r.a.y,  r.a.z,  r.d.x,  r.d.y,  r.d.z,  r.p0.x, r.p0.y, r.p0.z,
          r.p1.x, r.p1.y, r.p1.z, r.p2.x, r.p2.y, r.p2.z, r.t_min, r.t_max};
}

}  // namespace ru::dp
