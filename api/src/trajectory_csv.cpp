#include "slosh/api/trajectory_csv.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string_view>
#include <vector>

#include "slosh/core/motion/invalid_motion.hpp"

namespace slosh::api {

namespace {

constexpr std::string_view kPoseHeader{"t_s,x_m,y_m,z_m,qx,qy,qz,qw"};
constexpr std::string_view kByteOrderMark{"\xEF\xBB\xBF"};

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    out.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) return out;
    start = comma + 1;
  }
}

void strip_cr(std::string& line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
}

}  // namespace

TrajectorySamples read_trajectory_csv(std::istream& in, const std::string& source) {
  std::string line;
  std::size_t line_no = 1;
  auto fail = [&](const std::string& why) {
    throw InvalidMotion("line " + std::to_string(line_no),
                        source + " line " + std::to_string(line_no) + ": " + why);
  };
  const std::string headers = "t_s,x_mm,y_mm[,z_mm][,theta_deg] (mm and degrees) or " +
                              std::string(kPoseHeader) + " (metres and a unit quaternion)";
  if (!std::getline(in, line)) fail("empty; expected the header " + headers);
  strip_cr(line);
  // Spreadsheets save "CSV UTF-8" with a byte order mark before the header.
  if (line.starts_with(kByteOrderMark)) line.erase(0, kByteOrderMark.size());
  if (line == kPoseHeader) {
    std::ostringstream all;
    all << line << '\n' << in.rdbuf();
    std::istringstream again(all.str());
    return read_pose_csv(again, source);
  }
  // Copied: the views of split() point into `line`, which the next getline overwrites.
  const std::string header = line;
  const std::vector<std::string_view> names = split(header);
  const bool plain = names.size() >= 3 && names.size() <= 5 && names[0] == "t_s" &&
                     names[1] == "x_mm" && names[2] == "y_mm" &&
                     (names.size() < 4 || names[3] == "z_mm" || names[3] == "theta_deg") &&
                     (names.size() < 5 || (names[3] == "z_mm" && names[4] == "theta_deg"));
  if (!plain) fail("header \"" + line + "\" must be " + headers);
  TrajectorySamples s;
  std::vector<double>* columns[5] = {&s.t, &s.x, &s.y, nullptr, nullptr};
  double scale[5] = {1.0, 1e-3, 1e-3, 0.0, 0.0};
  for (std::size_t c = 3; c < names.size(); ++c) {
    const bool z = names[c] == "z_mm";
    columns[c] = z ? &s.z : &s.theta;
    scale[c] = z ? 1e-3 : std::numbers::pi / 180.0;
  }
  while (std::getline(in, line)) {
    ++line_no;
    strip_cr(line);
    if (line.empty()) continue;
    const std::vector<std::string_view> fields = split(line);
    if (fields.size() != names.size()) {
      fail(std::to_string(fields.size()) + " fields, the header has " +
           std::to_string(names.size()));
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v{};
      const auto [end, ec] =
          std::from_chars(fields[c].data(), fields[c].data() + fields[c].size(), v);
      if (ec != std::errc() || end != fields[c].data() + fields[c].size() || !std::isfinite(v)) {
        fail(std::string(names[c]) + " = \"" + std::string(fields[c]) +
             "\" must be a finite number");
      }
      columns[c]->push_back(v * scale[c]);
    }
  }
  return s;
}

}  // namespace slosh::api
