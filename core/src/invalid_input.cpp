#include "slosh/core/invalid_input.hpp"

#include <cmath>
#include <cstdio>

#include "text.hpp"

namespace slosh {

namespace {

std::string number(double v, bool integer) {
  if (!integer || !std::isfinite(v)) return detail::sig3(v);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

std::string with_unit(std::string text, std::string_view unit) {
  if (!unit.empty()) {
    text += ' ';
    text += unit;
  }
  return text;
}

std::string allowed_text(const InputBounds& b, std::string_view unit, bool integer) {
  const std::string text = bounds_text(b, [integer](double v) { return number(v, integer); });
  if (!std::isfinite(b.lo) && !std::isfinite(b.hi)) return text;
  return with_unit((std::isfinite(b.lo) && std::isfinite(b.hi) ? "in " : "") + text, unit);
}

bool integer_input(PlanInput input) {
  return input == PlanInput::kModes || input == PlanInput::kNBand ||
         input == PlanInput::kMaxPlans || input == PlanInput::kUncertaintySamples;
}

}  // namespace

std::string_view input_unit(PlanInput input) {
  switch (input) {
    case PlanInput::kContainerRadius:
    case PlanInput::kContainerHeight:
    case PlanInput::kFillHeight:
    case PlanInput::kStroke:
    case PlanInput::kEtaRestMax:
    case PlanInput::kEtaMotionMax:
    case PlanInput::kUniformResponse:
    case PlanInput::kLawResponse:
    case PlanInput::kFreeBoardMargin:
    case PlanInput::kFillHeightRange:
    case PlanInput::kContainerLength:
    case PlanInput::kContainerWidth:
      return "m";
    case PlanInput::kContainerOrientation:
      return "deg";
    case PlanInput::kFluidDensity:
      return "kg/m^3";
    case PlanInput::kFluidViscosity:
    case PlanInput::kViscosityRange:
      return "Pa s";
    case PlanInput::kMotionTime:
    case PlanInput::kMinRamp:
    case PlanInput::kRampsAndPlateaus:
    case PlanInput::kPlateauMin:
    case PlanInput::kRestTime:
    case PlanInput::kTimeLimit:
    case PlanInput::kIirSamplePeriod:
    case PlanInput::kLaw:
    case PlanInput::kSamplePeriod:
    case PlanInput::kMotionTimeMax:
    case PlanInput::kScanStep:
    case PlanInput::kWarmStart:
    case PlanInput::kDriveProfile:
      return "s";
    case PlanInput::kAMax:
      return "m/s^2";
    case PlanInput::kVMax:
    case PlanInput::kReferenceLevels:
      return "m/s";
    case PlanInput::kJMax:
      return "m/s^3";
    case PlanInput::kIirTau:
      return "1/s";
    case PlanInput::kSloshingModel:
      return "rad/s";
    case PlanInput::kModes:
    case PlanInput::kAlpha:
    case PlanInput::kZeta:
    case PlanInput::kWeights:
    case PlanInput::kPNotch:
    case PlanInput::kBand:
    case PlanInput::kNBand:
    case PlanInput::kTolRel:
    case PlanInput::kResidual:
    case PlanInput::kMaxPlans:
    case PlanInput::kCurveFactor:
    case PlanInput::kRefineExcess:
    case PlanInput::kOmegaError:
    case PlanInput::kUncertaintySamples:
    case PlanInput::kOmegaScale:
    case PlanInput::kHeightGain:
    case PlanInput::kWidthOmegaScale:
    case PlanInput::kWidthZeta:
      return "";
  }
  return "";
}

bool InputBounds::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above = lo_open ? value > lo : value >= lo;
  const bool below = hi_open ? value < hi : value <= hi;
  return above && below;
}

std::string bounds_text(const InputBounds& b, const std::function<std::string(double)>& number) {
  const bool has_lo = std::isfinite(b.lo);
  const bool has_hi = std::isfinite(b.hi);
  if (has_lo && has_hi) {
    return std::string(b.lo_open ? "(" : "[") + number(b.lo) + ", " + number(b.hi) +
           (b.hi_open ? ")" : "]");
  }
  if (has_lo) return (b.lo_open ? "> " : ">= ") + number(b.lo);
  if (has_hi) return (b.hi_open ? "< " : "<= ") + number(b.hi);
  return "finite";
}

std::string InvalidInput::allowed() const {
  return allowed_text(bounds, input_unit(input), integer_input(input));
}

InvalidInput out_of_range(PlanInput input, int index, double value, const InputBounds& bounds) {
  const bool integer = integer_input(input);
  InvalidInput e;
  e.input = input;
  e.index = index;
  e.value = value;
  e.bounds = bounds;
  std::string name(name_of(input));
  if (index >= 0) name += "[" + std::to_string(index) + "]";
  const std::string_view unit = input_unit(input);
  e.message = name + " = " + with_unit(number(value, integer), unit) + " must be finite and " +
              allowed_text(bounds, unit, integer);
  return e;
}

InvalidInput refused(PlanInput input, double value, const InputBounds& bounds,
                     std::string message) {
  InvalidInput e;
  e.input = input;
  e.value = value;
  e.bounds = bounds;
  e.message = std::move(message);
  return e;
}

std::optional<InvalidInput> first_out_of_range(std::initializer_list<BoundedValue> values) {
  for (const BoundedValue& v : values) {
    if (!v.bounds.contains(v.value)) return out_of_range(v.input, -1, v.value, v.bounds);
  }
  return std::nullopt;
}

}  // namespace slosh
