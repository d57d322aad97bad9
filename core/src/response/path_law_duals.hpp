#pragma once
// A 7-segment law along a planar path in dual numbers over the 7 durations (internal to the
// core): its state at every switch, the smooth pieces of its drive (never across a switch time
// or a time where s(t) crosses a join of the path, where the curvature jumps), and the drive on
// one piece. What the path sensitivities (path_sensitivity.hpp) integrate piece by piece.
//
// The pieces' ends move with the durations, and their derivatives follow: a switch time is a
// sum of durations, a crossing time t_c of s(t_c) = s_join has dt_c/dd = -(ds/dd at fixed t) /
// s'(t_c).

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "response/dual8.hpp"
#include "slosh/core/motion/planar_path.hpp"

namespace slosh::detail {

/// A smooth piece of the drive: [t_begin, t_end] on one segment of the law and one element of
/// the path, or the rest window.
struct DualPiece {
  Dual7 t_begin, t_end;
  std::size_t segment{}, element{};
  bool rest{};
};

/// The law's state at each segment start and its jerks, in duals.
struct PathLawDuals {
  std::array<Dual7, kSegments + 1> t_start{}, s_start{}, v_start{}, a_start{};
  std::array<Dual7, kSegments> jerk{};

  /// Sets the law's state for the durations d along `path` and returns the drive's smooth
  /// pieces, the rest window of `rest_time` last.
  std::vector<DualPiece> pieces(const PlanarPath& path, double rest_time,
                                const std::array<Dual7, kSegments>& d);
};

/// The longest step of each piece of `pieces` [s] (the law's state set by the pieces() that
/// returned them): at most h_max, and steps_per_period steps per turn of the heading on an arc at
/// the piece's largest rate |kappa s'| (s' is a quadratic on a segment: its largest magnitude is
/// at an end or at its vertex), as the stored responses bound theirs (planar_scheme.hpp).
[[nodiscard]] std::vector<double> piece_steps(const PathLawDuals& law, const PlanarPath& path,
                                              const std::vector<DualPiece>& pieces, double h_max,
                                              double steps_per_period);

/// The durations d as dual numbers: each the variable of its own lane (`variables`), or
/// constants.
[[nodiscard]] std::array<Dual7, kSegments> dual_durations(const double* d, bool variables);

/// The step counts a path sensitivity holds while a solver runs: at freeze(), one more than each
/// piece takes then; while later pieces keep that order (the same segment and element each),
/// every piece takes at least its frozen count, so the discrete response stays smooth in the
/// durations.
struct FrozenSteps {
  std::vector<std::size_t> count;  // least step count per piece
  std::vector<std::size_t> key;    // the pieces' (segment, element) at the freeze

  /// `h_max`: the longest step of each piece (piece_steps()).
  void freeze(const std::vector<DualPiece>& pieces, const std::vector<double>& h_max);
  /// The step count of each piece of `pieces`, its steps at most `h_max` of it long.
  [[nodiscard]] std::vector<std::size_t> steps(const std::vector<DualPiece>& pieces,
                                               const std::vector<double>& h_max) const;
};

/// The index of the stored step that holds t, of steps starting at `t0` (ascending).
[[nodiscard]] std::size_t step_index(const std::vector<double>& t0, double t);

/// The tangential and normal acceleration and the speed at one time of a piece.
struct PieceMotion {
  D8 acc, normal, speed;
};

/// The drive on one piece as functions of a dual time: the law's polynomial on its segment and
/// the path's element (a line or an arc of curvature kappa).
struct PieceDrive {
  bool rest{};
  double kappa{}, s_e{}, psi0{}, cos0{}, sin0{};
  D8 T_k, s_k, v_k, a_k, J_k, half_J, sixth_J, half_a;

  PieceDrive(const PlanarPath& path, const PathLawDuals& law, const DualPiece& piece) {
    const std::size_t k = piece.segment, e = piece.element;
    rest = piece.rest;
    const PlanarKinematics start = path.at(e, path.element_starts()[e], 1.0, 0.0, 0.0);
    psi0 = std::atan2(start.vy, start.vx);
    kappa = path.curvature(e);
    s_e = path.element_starts()[e];
    T_k = D8(law.t_start[k]);
    s_k = D8(law.s_start[k]);
    v_k = D8(law.v_start[k]);
    a_k = D8(law.a_start[k]);
    J_k = D8(law.jerk[k]);
    half_J = 0.5 * J_k;
    sixth_J = (1.0 / 6.0) * J_k;
    half_a = 0.5 * a_k;
    cos0 = std::cos(psi0);
    sin0 = std::sin(psi0);
  }

  /// The world-frame horizontal acceleration (a_x, a_y) at t (0 in the rest window).
  [[gnu::always_inline]] std::array<D8, 2> world(const D8& t) const {
    std::array<D8, 2> a{};
    if (rest) return a;
    const D8 u = t - T_k;
    const D8 acc = a_k + J_k * u;
    if (kappa == 0.0) {
      a[0] = cos0 * acc;
      a[1] = sin0 * acc;
      return a;
    }
    const D8 vel = v_k + u * (a_k + u * half_J);
    const D8 pos = s_k + u * (v_k + u * (half_a + u * sixth_J));
    const D8 psi = psi0 + kappa * (pos - s_e);
    D8 c, sn;
    dual_cos_sin(psi, c, sn);
    const D8 normal = kappa * (vel * vel);
    a[0] = acc * c - normal * sn;
    a[1] = acc * sn + normal * c;
    return a;
  }

  /// s'', kappa s'^2 and s' at t (the piece must not be the rest window).
  [[gnu::always_inline]] PieceMotion motion(const D8& t) const {
    const D8 u = t - T_k;
    PieceMotion m;
    m.acc = a_k + J_k * u;
    m.speed = v_k + u * (a_k + u * half_J);
    m.normal = kappa * (m.speed * m.speed);
    return m;
  }
};

}  // namespace slosh::detail
