#pragma once
// Numbers in texts that must name one double exactly.

#include <string>

namespace slosh::api {

/// A number that reads back as exactly `v`: number_text when its 10 digits do, else the fewest
/// digits (up to 17) that do. For a value quoted against a limit (0.04999999999999999 must not
/// print as 0.05 next to "allowed 0.05 to ...") and wherever a text must name one double (the
/// sample period in a plan's ETag).
[[nodiscard]] std::string exact_number_text(double v);

}  // namespace slosh::api
