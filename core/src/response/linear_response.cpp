#include "slosh/core/response/response.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace slosh {

namespace {

// exp(-sigma tau) (c1 C(tau) + c2 S(tau)) and its derivative, with C, S = cos, sin (under-damped),
// cosh, sinh (over-damped; as two decaying exponentials, so nothing overflows) or 1, tau.
ModeState homogeneous(const LinearModePiece& p, double tau) {
  switch (p.damping) {
    case LinearModePiece::Damping::kUnder: {
      const double e = std::exp(-p.sigma * tau);
      const double c = std::cos(p.wd * tau);
      const double sn = std::sin(p.wd * tau);
      return {e * (p.c1 * c + p.c2 * sn),
              e * ((-p.sigma * p.c1 + p.wd * p.c2) * c + (-p.sigma * p.c2 - p.wd * p.c1) * sn)};
    }
    case LinearModePiece::Damping::kCritical: {
      const double e = std::exp(-p.sigma * tau);
      return {e * (p.c1 + p.c2 * tau), e * (p.c2 - p.sigma * (p.c1 + p.c2 * tau))};
    }
    case LinearModePiece::Damping::kOver: {
      const double slow = p.slow;  // sigma - wd
      const double fast = p.sigma + p.wd;
      const double e1 = std::exp(-slow * tau), e2 = std::exp(-fast * tau);
      const double ec = 0.5 * (e1 + e2), es = 0.5 * (e1 - e2);
      const double dec = 0.5 * (-slow * e1 - fast * e2), des = 0.5 * (-slow * e1 + fast * e2);
      return {p.c1 * ec + p.c2 * es, p.c1 * dec + p.c2 * des};
    }
  }
  return {};
}

}  // namespace

double LinearModePiece::position(double tau) const {
  double x = r[0] + tau * (r[1] + tau * (r[2] + tau * r[3]));
  if (W != 0.0) {
    const double c = std::cos(W * tau);
    const double sn = std::sin(W * tau);
    x += P * c + Q * sn + tau * (U * c + V * sn);
  }
  if (damping != Damping::kUnder) return x + homogeneous(*this, tau).x;
  return x + std::exp(-sigma * tau) * (c1 * std::cos(wd * tau) + c2 * std::sin(wd * tau));
}

ModeState LinearModePiece::at(double tau) const {
  ModeState s;
  s.x = r[0] + tau * (r[1] + tau * (r[2] + tau * r[3]));
  s.x_dot = r[1] + tau * (2.0 * r[2] + tau * 3.0 * r[3]);
  if (W != 0.0) {
    const double c = std::cos(W * tau);
    const double sn = std::sin(W * tau);
    s.x += P * c + Q * sn + tau * (U * c + V * sn);
    s.x_dot += W * (-P * sn + Q * c) + (U * c + V * sn) + tau * W * (-U * sn + V * c);
  }
  const ModeState h = homogeneous(*this, tau);
  s.x += h.x;
  s.x_dot += h.x_dot;
  return s;
}

LinearResponse::LinearResponse(const SloshingModel& model, const MotionLaw& law, double rest_time)
    : gains_(model.eta_gain), motion_time_(law.duration()), end_time_(law.duration() + rest_time) {
  std::vector<LawPiece> pieces = law.pieces();
  LawPiece rest{motion_time_, end_time_};  // zero forcing
  pieces.push_back(rest);
  const int modes = model.modes();
  coefficients_.resize(pieces.size() * static_cast<std::size_t>(modes));
  for (const LawPiece& p : pieces) piece_begin_.push_back(p.t_begin);

  for (int m = 0; m < modes; ++m) {
    const double w = model.omega[static_cast<std::size_t>(m)];
    const double z = model.zeta;
    const double two_zw = 2.0 * z * w;
    const double w2 = w * w;
    ModeState state{};  // at rest at t = 0
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const LawPiece& p = pieces[k];
      LinearModePiece& c =
          coefficients_[k * static_cast<std::size_t>(modes) + static_cast<std::size_t>(m)];
      // Forcing f = -a: polynomial part q, harmonic part (fc, fs) at W.
      const std::array<double, 4> q{-p.poly[0], -p.poly[1], -p.poly[2], -p.poly[3]};
      c.r[3] = q[3] / w2;
      c.r[2] = (q[2] - 3.0 * two_zw * c.r[3]) / w2;
      c.r[1] = (q[1] - 2.0 * two_zw * c.r[2] - 6.0 * c.r[3]) / w2;
      c.r[0] = (q[0] - two_zw * c.r[1] - 2.0 * c.r[2]) / w2;
      c.W = p.harmonic_omega;
      if (c.W != 0.0) {
        const double fc = -p.harmonic_cos;
        const double fs = -p.harmonic_sin;
        const double W = c.W;
        const double kk = w2 - W * W;
        const double cc = two_zw * W;
        const double det = kk * kk + cc * cc;
        if (det > 1e-16 * w2 * w2) {
          // (w^2 - W^2) P + 2 z w W Q = fc ; (w^2 - W^2) Q - 2 z w W P = fs
          c.P = (kk * fc - cc * fs) / det;
          c.Q = (kk * fs + cc * fc) / det;
        } else {
          // Undamped resonance: x_p = tau (U cos + V sin).
          c.V = fc / (2.0 * W);
          c.U = -fs / (2.0 * W);
        }
      }
      c.sigma = z * w;
      if (z < 1.0) {
        c.damping = LinearModePiece::Damping::kUnder;
        c.wd = w * std::sqrt(1.0 - z * z);
      } else if (z == 1.0) {
        c.damping = LinearModePiece::Damping::kCritical;
        c.wd = 1.0;
      } else {
        c.damping = LinearModePiece::Damping::kOver;
        c.wd = w * std::sqrt((z - 1.0) * (z + 1.0));
        c.slow = w2 / (c.sigma + c.wd);  // sigma - wd without cancellation
      }
      // Homogeneous part matches the state at the piece start.
      LinearModePiece particular = c;
      particular.c1 = particular.c2 = 0.0;
      const ModeState p0 = particular.at(0.0);
      c.c1 = state.x - p0.x;
      c.c2 = (state.x_dot - p0.x_dot + c.sigma * c.c1) / c.wd;
      state = c.at(p.duration());
    }
  }
  double w_max = *std::max_element(model.omega.begin(), model.omega.end());
  peak_step_ = std::min(kMaxPeakStep, 2.0 * std::numbers::pi / w_max / kSamplesPerPeriod);
}

std::size_t LinearResponse::piece_index(double t) const {
  const auto it = std::upper_bound(piece_begin_.begin(), piece_begin_.end(), t);
  return static_cast<std::size_t>(it - piece_begin_.begin()) - 1;
}

ModeState LinearResponse::mode_state(int mode, double t) const {
  if (t <= 0.0) return {};
  const std::size_t k = piece_index(t);
  return coefficients_[k * gains_.size() + static_cast<std::size_t>(mode)].at(t - piece_begin_[k]);
}

double LinearResponse::eta(double t) const {
  if (t <= 0.0) return 0.0;
  const std::size_t k = piece_index(t);
  const double tau = t - piece_begin_[k];
  double eta = 0.0;
  for (std::size_t m = 0; m < gains_.size(); ++m) {
    eta += gains_[m] * coefficients_[k * gains_.size() + m].position(tau);
  }
  return eta;
}

}  // namespace slosh
