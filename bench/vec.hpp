// The benchmark's own tiny vector and sample types.
//
// The formulations under test are templates on the scalar type T, so the same
// source runs in float, in double, and with Counted<T> (below), which counts
// the arithmetic a formulation does. glm is not used here on purpose: glm's
// vectors do not accept a user-defined scalar such as Counted.
#pragma once

#include <cmath>
#include <cstdint>

namespace raykit::bench {

template <class T>
struct Vec3 {
    T x, y, z;
};

template <class T> Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T> Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T> Vec3<T> operator*(const T& s, const Vec3<T>& a) { return {s * a.x, s * a.y, s * a.z}; }
template <class T> T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T> Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// One ray and the sphere it is tested against. In float the layout is the
/// kit's own: Ray{origin, direction} followed by Sphere{center, radius}.
template <class T>
struct Sample {
    Vec3<T> o;   ///< ray origin
    Vec3<T> d;   ///< ray direction, any length but zero
    Vec3<T> c;   ///< sphere centre
    T r;         ///< sphere radius
};

/// The roots of the whole line, as the kit's raykit::Roots but in any type.
/// count is 0 (miss) or 2 (hit); the formulations do not single out the
/// tangent, which has measure zero among the benchmark's rays.
template <class T>
struct RootsOf {
    int count = 0;
    T t[2] = {T(0), T(0)};
};

template <class To, class From>
Sample<To> convert(const Sample<From>& s) {
    auto v = [](const Vec3<From>& a) { return Vec3<To>{To(a.x), To(a.y), To(a.z)}; };
    return {v(s.o), v(s.d), v(s.c), To(s.r)};
}

// --- counting the arithmetic ---------------------------------------------------

/// How many of each operation one call did. A "flop" below is one add,
/// subtract, multiply, divide or square root; sign changes, comparisons and
/// copysign are free, as they are for the hardware's floating-point pipes.
struct OpCount {
    std::int64_t add = 0, mul = 0, div = 0, sqrt = 0;
    /// Of the adds and multiplies, those fused in pairs (fused() below): one
    /// instruction each, where a lone add or multiply is one instruction too.
    std::int64_t fma = 0;
    std::int64_t flops() const { return add + mul + div + sqrt; }
};

/// The counter Counted<T> adds to; one thread at a time counts.
inline OpCount& op_count() {
    static OpCount count;
    return count;
}

/// A number that tallies every operation done on it in op_count(). Running a
/// formulation on Counted<float> once gives its exact operation count on the
/// path that ray takes, with no hand-counting to go stale.
template <class T>
struct Counted {
    T v;
    Counted() : v(0) {}
    Counted(T x) : v(x) {}  // NOLINT: implicit, so literals like T(2) work
    Counted operator-() const { return {-v}; }
};

template <class T> Counted<T> operator+(Counted<T> a, Counted<T> b) { ++op_count().add; return {a.v + b.v}; }
template <class T> Counted<T> operator-(Counted<T> a, Counted<T> b) { ++op_count().add; return {a.v - b.v}; }
template <class T> Counted<T> operator*(Counted<T> a, Counted<T> b) { ++op_count().mul; return {a.v * b.v}; }
template <class T> Counted<T> operator/(Counted<T> a, Counted<T> b) { ++op_count().div; return {a.v / b.v}; }
template <class T> bool operator<(Counted<T> a, Counted<T> b) { return a.v < b.v; }
template <class T> bool operator>(Counted<T> a, Counted<T> b) { return a.v > b.v; }
template <class T> bool operator<=(Counted<T> a, Counted<T> b) { return a.v <= b.v; }
template <class T> bool operator>=(Counted<T> a, Counted<T> b) { return a.v >= b.v; }
template <class T> Counted<T> sqrt(Counted<T> a) { ++op_count().sqrt; return {std::sqrt(a.v)}; }
template <class T> Counted<T> copysign(Counted<T> a, Counted<T> b) { return {std::copysign(a.v, b.v)}; }

/// a b + c with one rounding: the hardware's fused multiply-add. Counted as a
/// multiply and an add, as the peak measurement counts an FMA as two flops.
inline float fused(float a, float b, float c) { return std::fma(a, b, c); }
inline double fused(double a, double b, double c) { return std::fma(a, b, c); }
template <class T> Counted<T> fused(Counted<T> a, Counted<T> b, Counted<T> c) {
    ++op_count().mul;
    ++op_count().add;
    ++op_count().fma;
    return {fused(a.v, b.v, c.v)};
}

/// The plain number inside a scalar, counted or not.
template <class T> double value(T x) { return static_cast<double>(x); }
template <class T> double value(Counted<T> x) { return static_cast<double>(x.v); }

}  // namespace raykit::bench
