// rayunits units: 3-vectors for the golden models, with the operation order fixed.
//
// Every function here is a fixed sequence of single FP operations of the element type (the
// contract in docs/UNITS.md "Dataflow"):
//   vsub(u, v)  = (u.x - v.x, u.y - v.y, u.z - v.z)                       3 sub
//   cross(u, v) = (u.y*v.z - u.z*v.y, u.z*v.x - u.x*v.z, u.x*v.y - u.y*v.x)  6 mul, 3 sub
//                 (left product minus right product, each product rounded)
//   dot(u, v)   = (u.x*v.x + u.y*v.y) + u.z*v.z                            3 mul, 2 add
//                 (x and y products summed first, as in the dissertation §3.9; this is
//                  ru::num::dot3 / rtl ru_fp_dot3)
// Products are commutative in IEEE arithmetic (bit for bit), so only the order of the
// subtraction operands and of the additions matters.
#pragma once

#include "rayunits/num/fp.hpp"

namespace ru::units {

template <class T>
struct Vec3 {
  T x{}, y{}, z{};
  const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

using Vec3d = Vec3<double>;

template <class T>
Vec3<T> vsub(const Vec3<T>& u, const Vec3<T>& v) {
  return {u.x - v.x, u.y - v.y, u.z - v.z};
}

template <class T>
Vec3<T> cross(const Vec3<T>& u, const Vec3<T>& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}

template <class T>
T dot(const Vec3<T>& u, const Vec3<T>& v) {
  return (u.x * v.x + u.y * v.y) + u.z * v.z;
}

// Conversion of a double vector into T (each component rounded by ru::num::fp_cast<T>).
template <class T>
Vec3<T> vcast(const Vec3d& v) {
  return {ru::num::fp_cast<T>(v.x), ru::num::fp_cast<T>(v.y), ru::num::fp_cast<T>(v.z)};
}
template <class T>
Vec3d vdouble(const Vec3<T>& v) {
  return {ru::num::fp_to_double(v.x), ru::num::fp_to_double(v.y), ru::num::fp_to_double(v.z)};
}

// Lexicographic minimum of Kensler §3.10: l if l.x < r.x; r if l.x > r.x; then y, then z;
// l when all three compare equal (also when a comparison involves a NaN: both < and > are
// false). Returns true when l is chosen. Hardware: comparisons only (ru_fp_cmp lt), no
// arithmetic; +0 and -0 compare equal.
template <class T>
bool lex_first_is_min(const Vec3<T>& l, const Vec3<T>& r) {
  if (l.x < r.x) return true;
  if (l.x > r.x) return false;
  if (l.y < r.y) return true;
  if (l.y > r.y) return false;
  if (l.z < r.z) return true;
  if (l.z > r.z) return false;
  return true;
}

}  // namespace ru::units
