// The core's fast sin/cos kernel against long-double libm.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "response/sincos.hpp"

namespace slosh {
namespace test_sincos {

double ulp_error(double value, long double reference) {
  const long double ulp =
      std::max<long double>(std::abs(reference), 1e-300L) * std::numeric_limits<double>::epsilon();
  return static_cast<double>(std::abs(static_cast<long double>(value) - reference) / ulp);
}

TEST(FastSinCos, WithinTwoUlpOnRandomArguments) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> wide(-2e4, 2e4), narrow(-4.0, 4.0);
  double worst_sin = 0.0, worst_cos = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double x = i % 2 == 0 ? wide(rng) : narrow(rng);
    const detail::SinCos sc = detail::fast_sincos(x);
    const long double xl = x;
    // Absolute error relative to 1 for results near zero (the reduction's limit).
    worst_sin = std::max(worst_sin, std::min(ulp_error(sc.sin, std::sin(xl)),
                                             std::abs(static_cast<double>(sc.sin - std::sin(xl))) /
                                                 std::numeric_limits<double>::epsilon()));
    worst_cos = std::max(worst_cos, std::min(ulp_error(sc.cos, std::cos(xl)),
                                             std::abs(static_cast<double>(sc.cos - std::cos(xl))) /
                                                 std::numeric_limits<double>::epsilon()));
  }
  EXPECT_LT(worst_sin, 2.0);
  EXPECT_LT(worst_cos, 2.0);
}

TEST(FastSinCos, QuadrantsAndSpecialArguments) {
  for (double x : {0.0, -0.0, 1e-300, 0.5, 1.5707963267948966, 3.141592653589793, 4.71238898038469,
                   6.283185307179586, -2.356194490192345, 123456.789}) {
    const detail::SinCos sc = detail::fast_sincos(x);
    EXPECT_NEAR(sc.sin, static_cast<double>(std::sin(static_cast<long double>(x))), 4e-16) << x;
    EXPECT_NEAR(sc.cos, static_cast<double>(std::cos(static_cast<long double>(x))), 4e-16) << x;
  }
  // Beyond the reduction range the C library is used.
  const detail::SinCos big = detail::fast_sincos(1e12);
  EXPECT_EQ(big.sin, std::sin(1e12));
  EXPECT_TRUE(std::isnan(detail::fast_sincos(std::nan("")).sin));
}

}  // namespace test_sincos
}  // namespace slosh
