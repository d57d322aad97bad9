#include "slosh/core/motion/sample_smoothing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace slosh {

namespace {

/// Order of the penalised differences; D D^T then has half bandwidth kOrder.
constexpr std::size_t kOrder{4};
/// Order of the differences the noise is estimated from.
constexpr std::size_t kNoiseOrder{6};
/// median |N(0, 1)|.
constexpr double kMedianAbsNormal{0.6744897501960817};
/// The residual sum of squares is matched to n sigma^2 within this relative tolerance, or lambda
/// is bracketed to this relative width.
constexpr double kResidualTolerance{1e-3};
/// Noise at most this multiple of the largest |sample| is the samples' own round-off (a unit-norm
/// difference of values each rounded by up to eps/2 of them has a deviation of ~0.3 eps): such
/// samples are exact and are interpolated as they are.
constexpr double kExactNoise{16.0 * std::numeric_limits<double>::epsilon()};
/// Smallest lambda the search starts from [-]: the fit then moves the samples by ~1e-12 of
/// their fourth differences.
constexpr double kMinSmoothing{1e-12};
/// Multiple of the noise beyond which a sample no longer holds still with its end (rest_runs),
/// whatever the quantum [-].
constexpr double kRestNoise{4.0};

/// Coefficients of the divided difference of order K over samples j..j+K, scaled to unit norm.
/// Computed in times relative to the rows' span, so no spacing overflows the products.
template <std::size_t K>
std::array<double, K + 1> unit_difference(const std::vector<double>& t, std::size_t j) {
  std::array<double, K + 1> c{};
  const double span = t[j + K] - t[j];
  double norm = 0.0;
  for (std::size_t m = 0; m <= K; ++m) {
    double p = 1.0;
    for (std::size_t l = 0; l <= K; ++l) {
      if (l != m) p *= (t[j + m] - t[j + l]) / span;
    }
    c[m] = 1.0 / p;
    norm += c[m] * c[m];
  }
  norm = std::sqrt(norm);
  for (double& e : c) e /= norm;
  return c;
}

using Row = std::array<double, kOrder + 1>;

/// The penalty's rows and the band of D D^T (band[i][d] = (D D^T)(i, i - d)).
struct Penalty {
  std::vector<Row> rows;
  std::vector<Row> band;
};

Penalty penalty(const std::vector<double>& t) {
  Penalty p;
  const std::size_t m = t.size() - kOrder;
  p.rows.resize(m);
  for (std::size_t j = 0; j < m; ++j) p.rows[j] = unit_difference<kOrder>(t, j);
  p.band.assign(m, Row{});
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t d = 0; d <= kOrder && d <= i; ++d) {
      double s = 0.0;
      for (std::size_t q = 0; q + d <= kOrder; ++q) s += p.rows[i][q] * p.rows[i - d][q + d];
      p.band[i][d] = s;
    }
  }
  return p;
}

/// The residual y - g for lambda: Cholesky of the band I / lambda + D D^T, then D^T w.
std::vector<double> residual(const Penalty& p, const std::vector<double>& dy, double lambda,
                             std::size_t n) {
  const std::size_t m = p.band.size();
  std::vector<Row> l(m, Row{});  // l[i][d] = L(i, i - d)
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t d = std::min(kOrder, i); d >= 1; --d) {
      const std::size_t j = i - d;
      double s = p.band[i][d];
      // sum over k < j within both rows' bands: L(i, k) L(j, k), k = i - e = j - (e - d)
      for (std::size_t e = d + 1; e <= kOrder && e <= i; ++e) s -= l[i][e] * l[j][e - d];
      l[i][d] = s / l[j][0];
    }
    double s = p.band[i][0] + 1.0 / lambda;
    for (std::size_t e = 1; e <= kOrder && e <= i; ++e) s -= l[i][e] * l[i][e];
    l[i][0] = std::sqrt(s);
  }
  std::vector<double> w(dy);
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t e = 1; e <= kOrder && e <= i; ++e) w[i] -= l[i][e] * w[i - e];
    w[i] /= l[i][0];
  }
  for (std::size_t i = m; i-- > 0;) {
    for (std::size_t e = 1; e <= kOrder && i + e < m; ++e) w[i] -= l[i + e][e] * w[i + e];
    w[i] /= l[i][0];
  }
  std::vector<double> r(n, 0.0);
  for (std::size_t j = 0; j < m; ++j) {
    for (std::size_t q = 0; q <= kOrder; ++q) r[j + q] += p.rows[j][q] * w[j];
  }
  return r;
}

/// Samples within `tolerance` of the end sample, counted from the end `last` (or the first).
std::size_t still_run(const std::vector<double>& v, double tolerance, bool last) {
  const std::size_t n = v.size();
  const double end = last ? v.back() : v.front();
  std::size_t k = 0;
  while (k < n && std::abs(v[last ? n - 1 - k : k] - end) <= tolerance) ++k;
  return k >= kMinRestSamples ? k : 0;
}

double sum_of_squares(const std::vector<double>& r) {
  double s = 0.0;
  for (double e : r) s += e * e;
  return s;
}

}  // namespace

double sample_noise(const std::vector<double>& t, const std::vector<double>& v) {
  const std::size_t n = t.size();
  if (n < kMinSmoothedSamples) return 0.0;
  std::vector<double> d;
  d.reserve(n - kNoiseOrder);
  for (std::size_t j = 0; j + kNoiseOrder < n; ++j) {
    const auto c = unit_difference<kNoiseOrder>(t, j);
    // Relative to the row's first sample: the coefficients sum to 0 only up to round-off, and
    // a log holding still must give exactly 0.
    double s = 0.0;
    for (std::size_t q = 1; q <= kNoiseOrder; ++q) s += c[q] * (v[j + q] - v[j]);
    if (s != 0.0) d.push_back(std::abs(s));
  }
  if (d.empty()) return 0.0;
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid / kMedianAbsNormal;
}

RestRuns rest_runs(const std::vector<double>& v, double noise) {
  // Half the samples' quantum: a log rounded to q steps by multiples of q, so only samples that
  // repeat the end's value lie within q / 2 of it (and a last approach by one quantum is not
  // taken for rest); a log with continuous noise has a tiny smallest step, and only samples
  // repeated exactly hold still there.
  double quantum = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < v.size(); ++i) {
    const double step = std::abs(v[i] - v[i - 1]);
    if (step > 0.0) quantum = std::min(quantum, step);
  }
  const double tolerance = std::min(0.5 * quantum, kRestNoise * noise);
  return {still_run(v, tolerance, false), still_run(v, tolerance, true)};
}

SmoothedSamples smoothed_samples(const std::vector<double>& t, const std::vector<double>& v) {
  SmoothedSamples out{v, sample_noise(t, v), 0.0};
  out.rest = rest_runs(v, out.noise);
  double largest = 0.0;
  for (double e : v) largest = std::max(largest, std::abs(e));
  if (out.noise <= kExactNoise * largest) return out;
  const std::size_t n = t.size();
  const Penalty p = penalty(t);
  std::vector<double> dy(p.rows.size(), 0.0);
  for (std::size_t j = 0; j < dy.size(); ++j) {
    for (std::size_t q = 0; q <= kOrder; ++q) dy[j] += p.rows[j][q] * v[j + q];
  }
  const double target = static_cast<double>(n) * out.noise * out.noise;
  // f(log lambda) = log(RSS / target) rises with lambda; regula falsi (Illinois) on the bracket.
  auto f_of = [&](double log_lambda, std::vector<double>& r) {
    r = residual(p, dy, std::exp(log_lambda), n);
    const double rss = sum_of_squares(r);
    return rss > 0.0 ? std::log(rss / target) : -1e300;
  };
  std::vector<double> r;
  double a = std::log(kMinSmoothing), b = std::log(kMaxSmoothing);
  double fb = f_of(b, r);
  double chosen = b;
  if (fb > 0.0) {
    std::vector<double> ra;
    double fa = f_of(a, ra);
    if (fa >= 0.0) {
      r = ra;
      chosen = a;
    } else {
      fa = std::max(fa, -700.0);  // a residual of 0 (exact cubic pieces): keep the step finite
      int side = 0;
      for (int k = 0; k < 200; ++k) {
        double c = (a * fb - b * fa) / (fb - fa);
        if (!(c > a && c < b)) c = 0.5 * (a + b);
        const double fc = f_of(c, r);
        chosen = c;
        if (std::abs(fc) < kResidualTolerance || b - a < kResidualTolerance) break;
        if (fc > 0.0) {
          b = c;
          fb = fc;
          if (side == 1) fa *= 0.5;
          side = 1;
        } else {
          a = c;
          fa = std::max(fc, -700.0);
          if (side == -1) fb *= 0.5;
          side = -1;
        }
      }
    }
  }
  out.lambda = std::exp(chosen);
  for (std::size_t i = 0; i < n; ++i) out.value[i] = v[i] - r[i];
  return out;
}

}  // namespace slosh
