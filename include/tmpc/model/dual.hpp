// Forward-mode dual numbers for exact derivatives of the model.
//
// Dual<T> = v + d*eps with eps^2 = 0, so f(v + d eps) = f(v) + f'(v) d eps.
// Nesting (Dual<Dual<double>>) gives second directional derivatives, which the
// dynamics use for the velocity-product terms (J-dot q-dot) and the Jacobians of
// f(x, u, d) (thesis (5.5)). No finite differences anywhere outside tests.
#pragma once

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

namespace tmpc {

template <class T>
struct Dual {
  T v{};  // value
  T d{};  // derivative along the seeded direction

  Dual() = default;
  Dual(double value) : v(value), d(0.0) {}  // NOLINT: implicit from constants
  Dual(T value, T deriv) : v(value), d(deriv) {}

  Dual& operator+=(const Dual& o) { v += o.v; d += o.d; return *this; }
  Dual& operator-=(const Dual& o) { v -= o.v; d -= o.d; return *this; }
  Dual& operator*=(const Dual& o) { d = d * o.v + v * o.d; v *= o.v; return *this; }
  Dual& operator/=(const Dual& o) { *this = *this / o; return *this; }

  friend Dual operator+(const Dual& a, const Dual& b) { return {a.v + b.v, a.d + b.d}; }
  friend Dual operator-(const Dual& a, const Dual& b) { return {a.v - b.v, a.d - b.d}; }
  friend Dual operator-(const Dual& a) { return {-a.v, -a.d}; }
  friend Dual operator*(const Dual& a, const Dual& b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
  friend Dual operator/(const Dual& a, const Dual& b) {
    const T inv = T(1.0) / b.v;
    return {a.v * inv, (a.d - a.v * inv * b.d) * inv};
  }
  friend bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
  friend bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
  friend bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
  friend bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
  friend bool operator==(const Dual& a, const Dual& b) { return a.v == b.v && a.d == b.d; }
  friend bool operator!=(const Dual& a, const Dual& b) { return !(a == b); }
};

template <class T>
Dual<T> sin(const Dual<T>& a) {
  using std::cos;
  using std::sin;
  return {sin(a.v), cos(a.v) * a.d};
}
template <class T>
Dual<T> cos(const Dual<T>& a) {
  using std::cos;
  using std::sin;
  return {cos(a.v), -sin(a.v) * a.d};
}
template <class T>
Dual<T> sqrt(const Dual<T>& a) {
  using std::sqrt;
  const T s = sqrt(a.v);
  return {s, a.d / (T(2.0) * s)};
}

/// Scalars the model is instantiated for: plain, and one to three nested duals.
using D1 = Dual<double>;
using D2 = Dual<D1>;
using D3 = Dual<D2>;

/// Value of a (possibly nested) dual number, as a double.
inline double value_of(double x) { return x; }
template <class T>
double value_of(const Dual<T>& x) {
  return value_of(x.v);
}

}  // namespace tmpc

namespace Eigen {
template <class T>
struct NumTraits<tmpc::Dual<T>> : NumTraits<double> {
  using Real = tmpc::Dual<T>;
  using NonInteger = tmpc::Dual<T>;
  using Nested = tmpc::Dual<T>;
  using Literal = tmpc::Dual<T>;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 2 * NumTraits<T>::ReadCost,
    AddCost = 2 * NumTraits<T>::AddCost,
    MulCost = 3 * NumTraits<T>::MulCost
  };
};
template <class T, typename BinaryOp>
struct ScalarBinaryOpTraits<tmpc::Dual<T>, double, BinaryOp> {
  using ReturnType = tmpc::Dual<T>;
};
template <class T, typename BinaryOp>
struct ScalarBinaryOpTraits<double, tmpc::Dual<T>, BinaryOp> {
  using ReturnType = tmpc::Dual<T>;
};
}  // namespace Eigen
