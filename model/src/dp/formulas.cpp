// Today's ray-triangle units in the datapath IR (see rayunits/dp/formulas.hpp).
#include "rayunits/dp/formulas.hpp"

namespace ru::dp {

namespace {

struct V3 {
  int x, y, z;
};

// The vec.hpp operation orders (docs/UNITS.md "Dataflow").
V3 vsub(Graph& g, V3 u, V3 v) { return {g.sub(u.x, v.x), g.sub(u.y, v.y), g.sub(u.z, v.z)}; }
V3 cross(Graph& g, V3 u, V3 v) {
  const int x = g.sub(g.mul(u.y, v.z), g.mul(u.z, v.y));
  const int y = g.sub(g.mul(u.z, v.x), g.mul(u.x, v.z));
  const int z = g.sub(g.mul(u.x, v.y), g.mul(u.y, v.x));
  return {x, y, z};
}
int dot(Graph& g, V3 u, V3 v) {
  const int xy = g.add(g.mul(u.x, v.x), g.mul(u.y, v.y));
  return g.add(xy, g.mul(u.z, v.z));
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

// The common tail of the triangle graphs: hit = accept & t_min < t < t_max, and the outputs in
// the order every triangle design has them (V0 only when the design computes it, v0 >= 0).
void tri_outputs(Graph& g, const TriInputs& in, int accept, int t, int beta, int gamma, int V, int Va, int v0, int V1,
                 int V2) {
  const int in_range = g.land(g.lt(in.tmin, t), g.lt(t, in.tmax));
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

}  // namespace

Graph ray_tri_robust_graph(bool tie_break, bool reciprocal) {
  Graph g;
  const TriInputs in = tri_inputs(g);
  const V3 e0 = vsub(g, in.p1, in.p2);
  const V3 e1 = vsub(g, in.p2, in.p0);
  const V3 e2 = vsub(g, in.p0, in.p1);
  const int s0 = lex_first_is_min(g, in.p1, in.p2);
  const int s1 = lex_first_is_min(g, in.p2, in.p0);
  const int s2 = lex_first_is_min(g, in.p0, in.p1);
  // a - m_i as in the RTL: the three differences a - p_j beside the edges, then a selection
  // (the model's vsub(a, m_i) is one of them: the same operation on the same operands)
  const V3 ap0 = vsub(g, in.a, in.p0), ap1 = vsub(g, in.a, in.p1), ap2 = vsub(g, in.a, in.p2);
  const V3 am0 = select(g, s0, ap1, ap2);
  const V3 am1 = select(g, s1, ap2, ap0);
  const V3 am2 = select(g, s2, ap0, ap1);
  const int V0 = dot(g, cross(g, am0, in.d), e0);
  const int V1 = dot(g, cross(g, am1, in.d), e1);
  const int V2 = dot(g, cross(g, am2, in.d), e2);
  const V3 N = cross(g, e1, e0);
  const int V = dot(g, N, in.d);
  const int Va = dot(g, N, vsub(g, in.p2, in.a));
  int t, beta, gamma;
  if (reciprocal) {
    const int inv = g.div(g.constant(1.0), V);
    t = g.mul(Va, inv);
    beta = g.mul(V1, inv);
    gamma = g.mul(V2, inv);
  } else {
    t = g.div(Va, V);
    beta = g.div(V1, V);
    gamma = g.div(V2, V);
  }
  const int zero = g.constant(0.0);
  const int any_neg = g.lor(g.lor(g.lt(V0, zero), g.lt(V1, zero)), g.lt(V2, zero));
  const int any_pos = g.lor(g.lor(g.gt(V0, zero), g.gt(V1, zero)), g.gt(V2, zero));
  int ok = g.lnot(g.land(any_neg, any_pos));
  if (tie_break) {
    const int tie = g.lor(g.lor(g.land(g.eq(V0, zero), s0), g.land(g.eq(V1, zero), s1)), g.land(g.eq(V2, zero), s2));
    ok = g.land(ok, g.lnot(tie));
  }
  tri_outputs(g, in, ok, t, beta, gamma, V, Va, V0, V1, V2);
  return g;
}

Graph ray_tri_mt_graph() {
  Graph g;
  const TriInputs in = tri_inputs(g);
  const V3 e1 = vsub(g, in.p1, in.p0);
  const V3 e2 = vsub(g, in.p2, in.p0);
  const V3 s = vsub(g, in.a, in.p0);
  const V3 q = cross(g, in.d, e2);
  const V3 r = cross(g, s, e1);
  const int V = dot(g, q, e1);
  const int V1 = dot(g, q, s);
  const int V2 = dot(g, r, in.d);
  const int Va = dot(g, r, e2);
  const int one = g.constant(1.0);
  const int inv = g.div(one, V);
  const int beta = g.mul(V1, inv);
  const int gamma = g.mul(V2, inv);
  const int t = g.mul(Va, inv);
  const int sum = g.add(beta, gamma);
  const int zero = g.constant(0.0);
  const int inside = g.land(g.land(g.ge(beta, zero), g.ge(gamma, zero)), g.le(sum, one));
  tri_outputs(g, in, inside, t, beta, gamma, V, Va, -1, V1, V2);
  return g;
}

const std::vector<Design>& designs() {
  static const std::vector<Design> d = {
      {"ray_tri_robust", "Kensler Fig. 3.6 (units::ray_tri_robust, no tie-break)", [] { return ray_tri_robust_graph(); }},
      {"ray_tri_robust_tie", "Fig. 3.6 with its zero-volume tie-break", [] { return ray_tri_robust_graph(true); }},
      {"ray_tri_robust_recip", "Fig. 3.6, one reciprocal 1/V and three multiplications",
       [] { return ray_tri_robust_graph(false, true); }},
      {"ray_tri_mt", "Moller-Trumbore, Eq. 3.2 (units::ray_tri_mt)", [] { return ray_tri_mt_graph(); }},
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

std::vector<double> tri_inputs(const units::TriRecord& r) {
  return {r.a.x,  r.a.y,  r.a.z,  r.d.x,  r.d.y,  r.d.z,  r.p0.x, r.p0.y, r.p0.z,
          r.p1.x, r.p1.y, r.p1.z, r.p2.x, r.p2.y, r.p2.z, r.t_min, r.t_max};
}

}  // namespace ru::dp
