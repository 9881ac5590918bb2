#include "calibration/basis_spec.hpp"

#include <charconv>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

[[noreturn]] void bad(const std::string& term, const std::string& why) {
  throw core::InvalidInput("basis term '" + term + "' " + why +
                           " (expected polynomial:N[:legendre|raw] or fourier:N:F0)");
}

int parse_order(const std::string& text, const std::string& term) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 1) {
    bad(term, "has order '" + text + "', not a whole number ≥ 1");
  }
  return value;
}

core::BasisTerm parse_term(const std::string& term) {
  const auto fields = split(term, ':');
  if (fields.size() < 2) bad(term, "is incomplete");
  core::BasisTerm out;
  out.order = parse_order(fields[1], term);
  if (fields[0] == "polynomial") {
    out.kind = core::BasisKind::Polynomial;
    if (fields.size() > 3) bad(term, "has too many fields");
    if (fields.size() == 3) {
      if (fields[2] == "raw") {
        out.form = core::PolynomialForm::RawPower;
      } else if (fields[2] != "legendre") {
        bad(term, "has form '" + fields[2] + "'");
      }
    }
  } else if (fields[0] == "fourier") {
    out.kind = core::BasisKind::Fourier;
    if (fields.size() != 3) bad(term, "needs its fundamental F0");
    try {
      std::size_t used = 0;
      out.f0_per_c = std::stod(fields[2], &used);
      if (used != fields[2].size()) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      bad(term, "has fundamental '" + fields[2] + "', not a number");
    }
  } else {
    bad(term, "has kind '" + fields[0] + "'");
  }
  return out;
}

}  // namespace

core::Basis parse_basis(const std::string& spec,
                        const Eigen::Ref<const Eigen::VectorXd>& temperatures_c) {
  std::vector<core::BasisTerm> terms;
  for (const auto& term : split(spec, '+')) terms.push_back(parse_term(term));
  if (terms.empty()) throw core::InvalidInput("empty basis specification");
  return core::Basis(terms, core::TemperatureScaling::spanning(temperatures_c));
}

std::vector<core::Basis> parse_candidates(const std::vector<std::string>& specs,
                                          const Eigen::Ref<const Eigen::VectorXd>& temperatures_c) {
  std::vector<core::Basis> out;
  for (const auto& spec : specs) {
    const auto range = spec.find("..");
    if (range == std::string::npos) {
      out.push_back(parse_basis(spec, temperatures_c));
      continue;
    }
    // kind:LO..HI[:rest]
    const auto colon = spec.find(':');
    if (colon == std::string::npos || colon > range) bad(spec, "has a range without a kind");
    const std::string kind = spec.substr(0, colon);
    const auto after = spec.find(':', range);
    const std::string rest = after == std::string::npos ? "" : spec.substr(after);
    const int lo = parse_order(spec.substr(colon + 1, range - colon - 1), spec);
    const int hi = parse_order(
        spec.substr(range + 2, after == std::string::npos ? std::string::npos : after - range - 2),
        spec);
    if (hi < lo) bad(spec, "has an empty range");
    for (int n = lo; n <= hi; ++n) {
      out.push_back(parse_basis(kind + ":" + std::to_string(n) + rest, temperatures_c));
    }
  }
  return out;
}

}  // namespace tofcomp::calibration
