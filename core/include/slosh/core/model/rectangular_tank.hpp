#pragma once
// The geometry of an open rectangular container (SPEC §15), apart from its models so that a
// Format can hold it.

namespace slosh {

/// An open rectangular tank (cup, tray) with vertical walls, moved along a straight path.
struct RectangularTank {
  double length{0.12};  ///< L [m]: inner side along the tank's own x axis
  double width{0.08};   ///< W [m]: inner side along the tank's own y axis
  /// Angle from the direction of motion to the tank's x axis (its side L) [deg], in [-180, 180]:
  /// 0 puts L along the motion, 90 puts W along it. An acceleration a along the motion has the
  /// components a cos(phi) along L and a sin(phi) along W.
  double orientation_deg{0.0};
};

}  // namespace slosh
