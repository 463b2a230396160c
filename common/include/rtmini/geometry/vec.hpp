#pragma once
// Small fixed-size vector usable on host and device.
#include "rtmini/config.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini {

template <class T>
struct Vec3T {
  T x{}, y{}, z{};

  KOKKOS_INLINE_FUNCTION constexpr Vec3T() = default;
  KOKKOS_INLINE_FUNCTION constexpr Vec3T(T a, T b, T c) : x(a), y(b), z(c) {}
  KOKKOS_INLINE_FUNCTION constexpr explicit Vec3T(T s) : x(s), y(s), z(s) {}
  template <class U>
  KOKKOS_INLINE_FUNCTION constexpr explicit Vec3T(const Vec3T<U>& o)
      : x(static_cast<T>(o.x)), y(static_cast<T>(o.y)), z(static_cast<T>(o.z)) {}

  KOKKOS_INLINE_FUNCTION T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  KOKKOS_INLINE_FUNCTION T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }

  KOKKOS_INLINE_FUNCTION Vec3T& operator+=(const Vec3T& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Vec3T& operator-=(const Vec3T& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Vec3T& operator*=(T s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  KOKKOS_INLINE_FUNCTION Vec3T& operator*=(const Vec3T& o) {
    x *= o.x;
    y *= o.y;
    z *= o.z;
    return *this;
  }
};

using Vec3 = Vec3T<Real>;
using Vec3f = Vec3T<float>;
using Vec3d = Vec3T<double>;

template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator+(Vec3T<T> a, const Vec3T<T>& b) {
  return a += b;
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator-(Vec3T<T> a, const Vec3T<T>& b) {
  return a -= b;
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator-(const Vec3T<T>& a) {
  return {-a.x, -a.y, -a.z};
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator*(Vec3T<T> a, T s) {
  return a *= s;
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator*(T s, Vec3T<T> a) {
  return a *= s;
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator*(Vec3T<T> a, const Vec3T<T>& b) {
  return a *= b;
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> operator/(const Vec3T<T>& a, T s) {
  return {a.x / s, a.y / s, a.z / s};
}

template <class T>
KOKKOS_INLINE_FUNCTION T dot(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
KOKKOS_INLINE_FUNCTION T length_squared(const Vec3T<T>& a) {
  return dot(a, a);
}
template <class T>
KOKKOS_INLINE_FUNCTION T length(const Vec3T<T>& a) {
  return math::sqrt(dot(a, a));
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> normalize(const Vec3T<T>& a) {
  const T l = length(a);
  return l > T(0) ? a * (T(1) / l) : Vec3T<T>(T(0));
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> vmin(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> vmax(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> vabs(const Vec3T<T>& a) {
  return {math::fabs(a.x), math::fabs(a.y), math::fabs(a.z)};
}
template <class T>
KOKKOS_INLINE_FUNCTION T max_component(const Vec3T<T>& a) {
  return a.x > a.y ? (a.x > a.z ? a.x : a.z) : (a.y > a.z ? a.y : a.z);
}
template <class T>
KOKKOS_INLINE_FUNCTION int max_dimension(const Vec3T<T>& a) {
  return a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
}
template <class T>
KOKKOS_INLINE_FUNCTION bool is_finite(const Vec3T<T>& a) {
  return math::isfinite(a.x) && math::isfinite(a.y) && math::isfinite(a.z);
}
// Mirror reflection of incident direction d about normal n (both unit).
template <class T>
KOKKOS_INLINE_FUNCTION Vec3T<T> reflect(const Vec3T<T>& d, const Vec3T<T>& n) {
  return d - n * (T(2) * dot(d, n));
}

}  // namespace rtmini
