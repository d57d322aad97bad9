#pragma once
// Refusal of a spatial motion (a path, an arc, a sampled trajectory): which member, and a
// sentence with the value and what it may be. The API maps `member` onto its request field.

#include <stdexcept>
#include <string>

namespace slosh {

/// A motion the core cannot simulate or plan along.
class InvalidMotion : public std::invalid_argument {
 public:
  /// `member`: the offending part in core names ("segments[2]", "radius", "t[13]", "row 17");
  /// `message`: the whole sentence, which names the member itself.
  InvalidMotion(std::string member, const std::string& message)
      : std::invalid_argument(message), member_(std::move(member)) {}
  [[nodiscard]] const std::string& member() const { return member_; }

 private:
  std::string member_;
};

}  // namespace slosh
