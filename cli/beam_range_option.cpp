#include "cli/beam_range_option.hpp"

#include "cli/number_checks.hpp"
#include "core/error.hpp"

namespace tofcomp::cli {

CLI::Option* add_beams_option(CLI::App& cmd, std::string& beams) {
  return cmd
      .add_option("--beams", beams,
                  "Only beams FIRST:LAST (indices from 0, both included), or one index; "
                  "default: every beam")
      ->check(parsed_by([](const std::string& text) { parse_beam_range(text); }, "--beams ",
                        "FIRST:LAST"));
}

std::optional<ipc::socket::BeamRange> parse_beam_range(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const auto bad = [&] {
    return core::InvalidInput("--beams '" + text +
                              "': expected FIRST:LAST (beam indices, e.g. 0:360) or one index");
  };
  const auto index = [&](const std::string& part) {
    if (part.empty() || part.find_first_not_of("0123456789") != std::string::npos ||
        part.size() > 5) {
      throw bad();
    }
    const unsigned long value = std::stoul(part);
    if (value > ipc::socket::kMaxBeamIndex) throw bad();
    return static_cast<std::uint32_t>(value);
  };
  const auto colon = text.find(':');
  const std::uint32_t first = index(text.substr(0, colon));
  const std::uint32_t last = colon == std::string::npos ? first : index(text.substr(colon + 1));
  if (first > last) throw bad();
  return ipc::socket::BeamRange{first, last};
}

}  // namespace tofcomp::cli
