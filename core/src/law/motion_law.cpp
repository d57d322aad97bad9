#include "slosh/core/law/motion_law.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "slosh/core/response/peak_finder.hpp"

namespace slosh {

KinematicState LawPiece::at(double tau) const {
  const auto& p = poly;
  KinematicState s;
  s.acceleration = p[0] + tau * (p[1] + tau * (p[2] + tau * p[3]));
  s.jerk = p[1] + tau * (2.0 * p[2] + tau * 3.0 * p[3]);
  s.velocity =
      velocity_begin + tau * (p[0] + tau * (p[1] / 2.0 + tau * (p[2] / 3.0 + tau * p[3] / 4.0)));
  s.position =
      position_begin +
      tau * (velocity_begin +
             tau * (p[0] / 2.0 + tau * (p[1] / 6.0 + tau * (p[2] / 12.0 + tau * p[3] / 20.0))));
  if (harmonic_omega != 0.0) {
    const double w = harmonic_omega;
    const double c = std::cos(w * tau);
    const double sn = std::sin(w * tau);
    s.acceleration += harmonic_cos * c + harmonic_sin * sn;
    s.jerk += w * (-harmonic_cos * sn + harmonic_sin * c);
    s.velocity += (harmonic_cos * sn + harmonic_sin * (1.0 - c)) / w;
    s.position += harmonic_cos * (1.0 - c) / (w * w) + harmonic_sin * (tau / w - sn / (w * w));
  }
  return s;
}

MotionLaw::MotionLaw(std::string name, std::vector<LawPiece> pieces)
    : name_(std::move(name)), pieces_(std::move(pieces)) {
  double v = 0.0;
  double x = 0.0;
  for (LawPiece& p : pieces_) {
    if (!(p.t_end >= p.t_begin)) throw std::invalid_argument("law piece ends before it begins");
    p.velocity_begin = v;
    p.position_begin = x;
    const KinematicState end = p.at(p.duration());
    v = end.velocity;
    x = end.position;
  }
}

double MotionLaw::stroke() const {
  if (pieces_.empty()) return 0.0;
  return pieces_.back().at(pieces_.back().duration()).position;
}

std::vector<double> MotionLaw::breakpoints() const {
  std::vector<double> b;
  b.reserve(pieces_.size() + 1);
  b.push_back(0.0);
  for (const LawPiece& p : pieces_) b.push_back(p.t_end);
  return b;
}

KinematicState MotionLaw::at(double t) const {
  if (pieces_.empty() || t < 0.0) return {};
  if (t >= duration()) {
    const LawPiece& last = pieces_.back();
    KinematicState end = last.at(last.duration());
    return {end.position, 0.0, 0.0, 0.0};
  }
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                             [](double value, const LawPiece& p) { return value < p.t_end; });
  if (it == pieces_.end()) it = std::prev(pieces_.end());
  return it->at(t - it->t_begin);
}

KinematicSummary MotionLaw::summary() const {
  KinematicSummary s;
  for (const LawPiece& p : pieces_) {
    const double L = p.duration();
    if (L <= 0.0) continue;
    const bool harmonic =
        p.harmonic_omega != 0.0 && (p.harmonic_cos != 0.0 || p.harmonic_sin != 0.0);
    if (!harmonic && p.poly[2] == 0.0 && p.poly[3] == 0.0) {
      // Linear acceleration (7-segment, FIR-chain, sampled laws): a at the ends, constant jerk,
      // |v| at the ends and where a crosses zero — exact, and cheap for laws of many pieces.
      const KinematicState begin = p.at(0.0), end = p.at(L);
      s.a_peak_positive = std::max({s.a_peak_positive, begin.acceleration, end.acceleration});
      s.a_peak_negative = std::max({s.a_peak_negative, -begin.acceleration, -end.acceleration});
      s.j_peak = std::max(s.j_peak, std::abs(p.poly[1]));
      s.v_peak = std::max({s.v_peak, std::abs(begin.velocity), std::abs(end.velocity)});
      if (p.poly[1] != 0.0) {
        const double root = -p.poly[0] / p.poly[1];
        if (root > 0.0 && root < L) s.v_peak = std::max(s.v_peak, std::abs(p.at(root).velocity));
      }
      continue;
    }
    // Polynomial pieces are at most cubic in a; harmonic ones oscillate at most a few times, so
    // 64 samples with local refinement locate every extremum.
    const double step = L / 64.0;
    auto field = [&](double (*get)(const KinematicState&)) {
      return [&p, get](double tau) { return get(p.at(tau)); };
    };
    auto a = field([](const KinematicState& k) { return k.acceleration; });
    auto neg_a = field([](const KinematicState& k) { return -k.acceleration; });
    auto v = field([](const KinematicState& k) { return std::abs(k.velocity); });
    auto j = field([](const KinematicState& k) { return std::abs(k.jerk); });
    s.a_peak_positive = std::max(s.a_peak_positive, find_max(a, 0.0, L, step).value);
    s.a_peak_negative = std::max(s.a_peak_negative, find_max(neg_a, 0.0, L, step).value);
    s.v_peak = std::max(s.v_peak, find_max(v, 0.0, L, step).value);
    s.j_peak = std::max(s.j_peak, find_max(j, 0.0, L, step).value);
  }
  return s;
}

MotionLaw MotionLaw::scaled(double factor) const {
  std::vector<LawPiece> pieces = pieces_;
  for (LawPiece& p : pieces) {
    for (double& c : p.poly) c *= factor;
    p.harmonic_cos *= factor;
    p.harmonic_sin *= factor;
  }
  return MotionLaw(name_, std::move(pieces));
}

MotionLaw make_poly5_law(double stroke, double motion_time) {
  const double T = motion_time;
  LawPiece p{0.0,
             T,
             {0.0, 60.0 * stroke / std::pow(T, 3), -180.0 * stroke / std::pow(T, 4),
              120.0 * stroke / std::pow(T, 5)}};
  return MotionLaw("poly5", {p});
}

MotionLaw make_cycloidal_law(double stroke, double motion_time) {
  const double T = motion_time;
  LawPiece p{0.0, T};
  p.harmonic_omega = 2.0 * std::numbers::pi / T;
  p.harmonic_sin = 2.0 * std::numbers::pi * stroke / (T * T);
  return MotionLaw("cycloidal", {p});
}

MotionLaw make_modified_trapezoid_law(double stroke, double motion_time) {
  const double T = motion_time;
  const double w = 4.0 * std::numbers::pi / T;
  auto piece = [T](double u0, double u1) { return LawPiece{u0 * T, u1 * T}; };
  std::vector<LawPiece> pieces{piece(0.0, 0.125), piece(0.125, 0.375), piece(0.375, 0.625),
                               piece(0.625, 0.875), piece(0.875, 1.0)};
  pieces[0].harmonic_omega = w;
  pieces[0].harmonic_sin = 1.0;
  pieces[1].poly[0] = 1.0;
  pieces[2].harmonic_omega = w;
  pieces[2].harmonic_cos = 1.0;
  pieces[3].poly[0] = -1.0;
  pieces[4].harmonic_omega = w;
  pieces[4].harmonic_cos = -1.0;
  // Unit plateau first; the exact stroke of that law fixes C_a (= 4.888 s/T^2).
  MotionLaw unit("modified_trapezoid", std::move(pieces));
  return unit.scaled(stroke / unit.stroke());
}

MotionLaw piecewise_linear_law(std::string name, const std::vector<double>& t,
                               const std::vector<double>& a) {
  std::vector<LawPiece> pieces(t.size() - 1);
  for (std::size_t k = 0; k + 1 < t.size(); ++k) {
    LawPiece& p = pieces[k];
    p.t_begin = t[k];
    p.t_end = t[k + 1];
    p.poly = {a[k], (a[k + 1] - a[k]) / (t[k + 1] - t[k]), 0.0, 0.0};
  }
  return MotionLaw(std::move(name), std::move(pieces));
}

}  // namespace slosh
