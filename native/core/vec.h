// Small vector types shared by host and device code. Plain structs (no CUDA headers) so the
// same physics compiles with g++ for the CPU backend and nvcc for the CUDA backend.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(_MSC_VER) && !defined(__CUDA_ARCH__)
#include <intrin.h>
#endif
#if (defined(__SSE__) || defined(_M_X64)) && !defined(__CUDA_ARCH__)
#include <xmmintrin.h>
#endif

#if defined(__CUDACC__)
#define PBF_HD __host__ __device__ __forceinline__
// A rare path kept out of line on the device, so its registers do not weigh on the hot code
// around the call.
#define PBF_HD_COLD __host__ __device__ __noinline__ inline
#else
#define PBF_HD inline
#define PBF_HD_COLD inline
#endif

namespace pbf {

struct Vec3 {
    float x, y, z;
};

// 16-byte aligned so the device loads and stores it with one 128-bit access.
struct alignas(16) Vec4 {
    float x, y, z, w;
};

PBF_HD Vec3 xyz(const Vec4& v) { return Vec3{v.x, v.y, v.z}; }
PBF_HD Vec4 make_vec4(const Vec3& v, float w) { return Vec4{v.x, v.y, v.z, w}; }

PBF_HD Vec3 operator+(Vec3 a, Vec3 b) { return Vec3{a.x + b.x, a.y + b.y, a.z + b.z}; }
PBF_HD Vec3 operator-(Vec3 a, Vec3 b) { return Vec3{a.x - b.x, a.y - b.y, a.z - b.z}; }
PBF_HD Vec3 operator-(Vec3 a) { return Vec3{-a.x, -a.y, -a.z}; }
PBF_HD Vec3 operator*(Vec3 a, float s) { return Vec3{a.x * s, a.y * s, a.z * s}; }
PBF_HD Vec3 operator*(float s, Vec3 a) { return Vec3{a.x * s, a.y * s, a.z * s}; }
PBF_HD Vec3& operator+=(Vec3& a, Vec3 b) {
    a.x += b.x;
    a.y += b.y;
    a.z += b.z;
    return a;
}
PBF_HD Vec3& operator-=(Vec3& a, Vec3 b) {
    a.x -= b.x;
    a.y -= b.y;
    a.z -= b.z;
    return a;
}
PBF_HD float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PBF_HD Vec3 cross(Vec3 a, Vec3 b) { return Vec3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
PBF_HD float length_sq(Vec3 a) { return dot(a, a); }
PBF_HD float length(Vec3 a) { return sqrtf(dot(a, a)); }
PBF_HD Vec3 min3(Vec3 a, Vec3 b) { return Vec3{fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)}; }
PBF_HD Vec3 max3(Vec3 a, Vec3 b) { return Vec3{fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)}; }
PBF_HD float clampf(float v, float lo, float hi) { return fminf(fmaxf(v, lo), hi); }

// 1/sqrt(x) and a/b for the neighbour loops: one special-function instruction each on the GPU
// (about 2 ulp) instead of the IEEE-exact sequences; exact on the CPU.
PBF_HD float inv_sqrt(float x) {
#if defined(__CUDA_ARCH__)
    return rsqrtf(x);
#elif defined(__SSE__) || defined(_M_X64)
    // x86: the 12-bit estimate and one Newton step (~2 ulp, like the GPU's) cost far less than
    // sqrtss + divss in the CPU backend's neighbour loops. Callers pass x > 1e-24.
    const float y = _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x)));
    return y * (1.5f - 0.5f * x * y * y);
#else
    return 1.0f / std::sqrt(x);
#endif
}
PBF_HD float fast_div(float a, float b) {
#if defined(__CUDA_ARCH__)
    return __fdividef(a, b);
#else
    return a / b;
#endif
}

// The float with these bits, and back (non-negative floats order like their bit patterns, so
// an unsigned atomic max finds the largest).
template <class To, class From>
PBF_HD To bit_cast_32(From v) {
    static_assert(sizeof(To) == 4 && sizeof(From) == 4, "32-bit values only");
    To out;
    memcpy(&out, &v, sizeof out);  // a register move on host and device
    return out;
}
PBF_HD float float_from_bits(uint32_t u) { return bit_cast_32<float>(u); }
PBF_HD uint32_t bits_from_float(float f) { return bit_cast_32<uint32_t>(f); }

// Index of the lowest set bit of a non-zero mask.
PBF_HD uint32_t lowest_bit(uint32_t mask) {
#if defined(__CUDA_ARCH__)
    return static_cast<uint32_t>(__ffs(static_cast<int>(mask)) - 1);
#elif defined(_MSC_VER)
    unsigned long k;
    _BitScanForward(&k, mask);
    return static_cast<uint32_t>(k);
#else
    return static_cast<uint32_t>(__builtin_ctz(mask));
#endif
}

// Row-major 3x3 rotation; columns are the body axes in world space.
struct Mat3 {
    float m[9];
};
PBF_HD Vec3 mul(const Mat3& r, Vec3 v) {
    return Vec3{r.m[0] * v.x + r.m[1] * v.y + r.m[2] * v.z, r.m[3] * v.x + r.m[4] * v.y + r.m[5] * v.z,
                r.m[6] * v.x + r.m[7] * v.y + r.m[8] * v.z};
}
PBF_HD Vec3 mul_transpose(const Mat3& r, Vec3 v) {
    return Vec3{r.m[0] * v.x + r.m[3] * v.y + r.m[6] * v.z, r.m[1] * v.x + r.m[4] * v.y + r.m[7] * v.z,
                r.m[2] * v.x + r.m[5] * v.y + r.m[8] * v.z};
}

}  // namespace pbf
