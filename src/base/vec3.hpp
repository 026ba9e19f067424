#pragma once
// A plain 3-vector and 3x3 matrix: the only linear algebra the hot loops need. (Eigen is used where
// dense solves are needed, in the continuum model.)
#include <cmath>

namespace tumble {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(double a, double b, double c) : x(a), y(b), z(c) {}
  constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  Vec3& operator*=(double s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
};

inline constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline constexpr Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
inline constexpr Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline constexpr Vec3 operator*(const Vec3& a, double s) { return {s * a.x, s * a.y, s * a.z}; }
inline constexpr double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline constexpr double norm2(const Vec3& a) { return dot(a, a); }

// Row-major 3x3 matrix, used for the tumbler orientation (tumbler frame -> lab frame).
struct Mat3 {
  double a[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  static Mat3 identity() { return Mat3{}; }
  // Rotation by `angle` (radians, right-handed) about the unit vector `u` (Rodrigues).
  static Mat3 rotation(const Vec3& u, double angle) {
    const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    Mat3 m;
    m.a[0][0] = c + u.x * u.x * t;
    m.a[0][1] = u.x * u.y * t - u.z * s;
    m.a[0][2] = u.x * u.z * t + u.y * s;
    m.a[1][0] = u.y * u.x * t + u.z * s;
    m.a[1][1] = c + u.y * u.y * t;
    m.a[1][2] = u.y * u.z * t - u.x * s;
    m.a[2][0] = u.z * u.x * t - u.y * s;
    m.a[2][1] = u.z * u.y * t + u.x * s;
    m.a[2][2] = c + u.z * u.z * t;
    return m;
  }
  Vec3 operator*(const Vec3& v) const {
    return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
            a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
            a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
  }
  // Transpose times vector: the inverse rotation.
  Vec3 tmul(const Vec3& v) const {
    return {a[0][0] * v.x + a[1][0] * v.y + a[2][0] * v.z,
            a[0][1] * v.x + a[1][1] * v.y + a[2][1] * v.z,
            a[0][2] * v.x + a[1][2] * v.y + a[2][2] * v.z};
  }
  Mat3 operator*(const Mat3& o) const {
    Mat3 m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        m.a[i][j] = a[i][0] * o.a[0][j] + a[i][1] * o.a[1][j] + a[i][2] * o.a[2][j];
    return m;
  }
};

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double deg2rad(double d) { return d * kPi / 180.0; }
inline constexpr double rad2deg(double r) { return r * 180.0 / kPi; }

}  // namespace tumble
