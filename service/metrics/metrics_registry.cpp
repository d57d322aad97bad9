#include "metrics/metrics_registry.hpp"

#include <cstdio>
#include <utility>

namespace slosh::service {

std::string label_value(std::string_view value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out;
}

void MetricsText::family(std::string_view name, std::string_view type, std::string_view help) {
  out_ << "# HELP " << name << ' ' << help << "\n# TYPE " << name << ' ' << type << '\n';
}

void MetricsText::sample(std::string_view name, std::string_view labels, std::uint64_t value) {
  out_ << name;
  if (!labels.empty()) out_ << '{' << labels << '}';
  out_ << ' ' << value << '\n';
}

void MetricsText::sample(std::string_view name, std::string_view labels, double value) {
  out_ << name;
  if (!labels.empty()) out_ << '{' << labels << '}';
  out_ << ' ' << value << '\n';
}

void MetricsText::exact_sample(std::string_view name, double value) {
  char number[64];
  std::snprintf(number, sizeof number, "%.17g", value);
  out_ << name << ' ' << number << '\n';
}

void MetricsText::bucket(std::string_view name, std::string_view labels, std::string_view le,
                         std::uint64_t n) {
  out_ << name << "_bucket{" << labels << ",le=\"" << le << "\"} " << n << '\n';
}

std::string MetricsText::bound_text(double bound) {
  std::ostringstream text;
  text << bound;
  return text.str();
}

void MetricsRegistry::add(Collector collector) {
  collectors_.push_back(std::move(collector));
}

std::string MetricsRegistry::render() const {
  MetricsText text;
  for (const Collector& collect : collectors_) collect(text);
  return text.str();
}

}  // namespace slosh::service
