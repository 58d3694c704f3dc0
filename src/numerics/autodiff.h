// Forward-mode automatic differentiation to second order: a scalar that carries its value, its
// gradient and its (dense, symmetric) Hessian with respect to N variables.
//
// Meant for small per-element functions (a triangle, a hinge) where deriving the Hessian by hand is
// not worth the risk. Every operation applies the chain rule to second order, so the cost of one
// operation is O(N^2); keep N small (<= 18) and the expression short.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace flatmorph {

template <int N>
struct Dual {
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Hessian = Eigen::Matrix<double, N, N>;

  double value = 0.0;
  Gradient gradient = Gradient::Zero();
  Hessian hessian = Hessian::Zero();

  Dual() = default;
  // A constant (zero derivatives); implicit so that doubles mix freely with duals.
  Dual(double v) : value(v) {}  // NOLINT(google-explicit-constructor)

  // The variable number `index` (0-based) with the given value.
  static Dual variable(double v, int index) {
    Dual d(v);
    d.gradient(index) = 1.0;
    return d;
  }

  Dual& operator+=(const Dual& b) { return *this = *this + b; }
  Dual& operator-=(const Dual& b) { return *this = *this - b; }
  Dual& operator*=(const Dual& b) { return *this = *this * b; }
  Dual& operator/=(const Dual& b) { return *this = *this / b; }

  // The chain rule for f(a) given f(a), f'(a), f''(a).
  static Dual chain(const Dual& a, double f, double df, double ddf) {
    Dual r(f);
    r.gradient = df * a.gradient;
    r.hessian = df * a.hessian + ddf * a.gradient * a.gradient.transpose();
    return r;
  }

  // The chain rule for f(a, b) given f and its first and second partial derivatives.
  static Dual chain(const Dual& a, const Dual& b, double f, double fa, double fb, double faa,
                    double fab, double fbb) {
    Dual r(f);
    r.gradient = fa * a.gradient + fb * b.gradient;
    const Hessian cross = a.gradient * b.gradient.transpose();
    r.hessian = fa * a.hessian + fb * b.hessian + faa * a.gradient * a.gradient.transpose() +
                fab * (cross + cross.transpose()) + fbb * b.gradient * b.gradient.transpose();
    return r;
  }
};

template <int N>
Dual<N> operator-(const Dual<N>& a) {
  Dual<N> r(-a.value);
  r.gradient = -a.gradient;
  r.hessian = -a.hessian;
  return r;
}

template <int N>
Dual<N> operator+(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.value + b.value);
  r.gradient = a.gradient + b.gradient;
  r.hessian = a.hessian + b.hessian;
  return r;
}

template <int N>
Dual<N> operator-(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.value - b.value);
  r.gradient = a.gradient - b.gradient;
  r.hessian = a.hessian - b.hessian;
  return r;
}

template <int N>
Dual<N> operator*(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.value * b.value);
  r.gradient = b.value * a.gradient + a.value * b.gradient;
  const typename Dual<N>::Hessian cross = a.gradient * b.gradient.transpose();
  r.hessian = b.value * a.hessian + a.value * b.hessian + cross + cross.transpose();
  return r;
}

template <int N>
Dual<N> operator/(const Dual<N>& a, const Dual<N>& b) {
  const double inv = 1.0 / b.value;
  const double q = a.value * inv;
  // f = a/b: fa = 1/b, fb = -a/b^2, faa = 0, fab = -1/b^2, fbb = 2a/b^3.
  return Dual<N>::chain(a, b, q, inv, -q * inv, 0.0, -inv * inv, 2.0 * q * inv * inv);
}

// Mixed operations with plain doubles (cheaper than promoting the double to a Dual).
template <int N>
Dual<N> operator+(const Dual<N>& a, double b) {
  Dual<N> r = a;
  r.value += b;
  return r;
}
template <int N>
Dual<N> operator+(double a, const Dual<N>& b) {
  return b + a;
}
template <int N>
Dual<N> operator-(const Dual<N>& a, double b) {
  return a + (-b);
}
template <int N>
Dual<N> operator-(double a, const Dual<N>& b) {
  return -b + a;
}
template <int N>
Dual<N> operator*(const Dual<N>& a, double b) {
  Dual<N> r(a.value * b);
  r.gradient = b * a.gradient;
  r.hessian = b * a.hessian;
  return r;
}
template <int N>
Dual<N> operator*(double a, const Dual<N>& b) {
  return b * a;
}
template <int N>
Dual<N> operator/(const Dual<N>& a, double b) {
  return a * (1.0 / b);
}
template <int N>
Dual<N> operator/(double a, const Dual<N>& b) {
  const double inv = 1.0 / b.value;
  return Dual<N>::chain(b, a * inv, -a * inv * inv, 2.0 * a * inv * inv * inv);
}

// Comparisons look at values only (branches in the differentiated function pick a formula).
template <int N>
bool operator<(const Dual<N>& a, const Dual<N>& b) {
  return a.value < b.value;
}
template <int N>
bool operator>(const Dual<N>& a, const Dual<N>& b) {
  return a.value > b.value;
}
template <int N>
bool operator<=(const Dual<N>& a, const Dual<N>& b) {
  return a.value <= b.value;
}
template <int N>
bool operator>=(const Dual<N>& a, const Dual<N>& b) {
  return a.value >= b.value;
}
template <int N>
bool operator==(const Dual<N>& a, const Dual<N>& b) {
  return a.value == b.value;
}
template <int N>
bool operator!=(const Dual<N>& a, const Dual<N>& b) {
  return a.value != b.value;
}

template <int N>
Dual<N> sqrt(const Dual<N>& a) {
  const double s = std::sqrt(a.value);
  return Dual<N>::chain(a, s, 0.5 / s, -0.25 / (s * a.value));
}

template <int N>
Dual<N> sin(const Dual<N>& a) {
  const double s = std::sin(a.value);
  return Dual<N>::chain(a, s, std::cos(a.value), -s);
}

template <int N>
Dual<N> cos(const Dual<N>& a) {
  const double c = std::cos(a.value);
  return Dual<N>::chain(a, c, -std::sin(a.value), -c);
}

template <int N>
Dual<N> exp(const Dual<N>& a) {
  const double e = std::exp(a.value);
  return Dual<N>::chain(a, e, e, e);
}

template <int N>
Dual<N> log(const Dual<N>& a) {
  const double inv = 1.0 / a.value;
  return Dual<N>::chain(a, std::log(a.value), inv, -inv * inv);
}

// a^n for an integer n (n may be negative or zero).
template <int N>
Dual<N> pow(const Dual<N>& a, int n) {
  if (n == 0) return Dual<N>(1.0);
  const double p2 = n == 1 ? 0.0 : std::pow(a.value, n - 2);  // a^(n-2), unused when n == 1
  const double p1 = n == 1 ? 1.0 : p2 * a.value;
  return Dual<N>::chain(a, p1 * a.value, n * p1, n * (n - 1) * p2);
}

// The angle of the point (x, y), as std::atan2.
template <int N>
Dual<N> atan2(const Dual<N>& y, const Dual<N>& x) {
  const double r2 = x.value * x.value + y.value * y.value;
  const double r4 = r2 * r2;
  // f_y = x/r^2, f_x = -y/r^2, f_yy = -2xy/r^4, f_yx = (y^2 - x^2)/r^4, f_xx = 2xy/r^4.
  return Dual<N>::chain(y, x, std::atan2(y.value, x.value), x.value / r2, -y.value / r2,
                        -2.0 * x.value * y.value / r4, (y.value * y.value - x.value * x.value) / r4,
                        2.0 * x.value * y.value / r4);
}

// sqrt(a^2 + b^2) without intermediate overflow in the value.
template <int N>
Dual<N> hypot(const Dual<N>& a, const Dual<N>& b) {
  const double r = std::hypot(a.value, b.value);
  const double r3 = r * r * r;
  return Dual<N>::chain(a, b, r, a.value / r, b.value / r, b.value * b.value / r3,
                        -a.value * b.value / r3, a.value * a.value / r3);
}

}  // namespace flatmorph
