#include "cli/junction_recheck_format.hpp"

#include <fmt/format.h>

#include "cli/search_format.hpp"

namespace tofcomp::cli {
namespace {

nlohmann::json start_json(const calibration::JunctionDynamics& d, const std::vector<core::Term>& kept) {
  return {{"rise_k", d.rise_k}, {"time_constant_s", d.time_constant_s},
          {"kept", term_descriptions(kept)}};
}

}  // namespace

nlohmann::json to_json(const calibration::JunctionRecheck& r) {
  nlohmann::json out = {{"first", r.first_from_ranges ? "ranges" : "case_log"},
                        {"from_ranges", start_json(r.from_ranges, r.kept_from_ranges)},
                        {"from_case_log", start_json(r.from_case_log, r.kept_from_case_log)},
                        {"chosen", r.case_log_chosen ? "case_log" : "ranges"},
                        {"error", r.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.error)}};
  if (r.error.empty()) {
    out["common_ranges"] = r.common_ranges;
    out["from_ranges_per_range"] = r.from_ranges_per_range();
    out["from_case_log_per_range"] = r.from_case_log_per_range();
  }
  return out;
}

std::string junction_recheck_text(const calibration::JunctionRecheck& r) {
  const char* first = r.first_from_ranges ? "the ranges'" : "the case log's";
  const char* other = r.first_from_ranges ? "the case log's" : "the ranges'";
  std::string out = fmt::format(
      "the junction re-checked: training took {} (the ranges' rise {:.2f} K, {:.1f} s{}; the case "
      "log's {:.2f} K, {:.1f} s) and the search kept {}; ",
      r.first_from_ranges ? "it from the ranges" : "the case log's", r.from_ranges.rise_k,
      r.from_ranges.time_constant_s,
      r.first_from_ranges ? "" : ", its blocks' test not rejecting the case log's",
      r.from_case_log.rise_k, r.from_case_log.time_constant_s,
      effect_names_or_nothing(r.kept_first()));
  if (!r.error.empty())
    return out + fmt::format("from {} junction: {}; {} stands\n", other, r.error, first);
  out += fmt::format(
      "from {} it keeps {}; held-out log-likelihood per range ({} scored by both) "
      "{:.4f} from the ranges', {:.4f} from the case log's: {}\n",
      other, effect_names_or_nothing(r.kept_again()), r.common_ranges, r.from_ranges_per_range(),
      r.from_case_log_per_range(),
      r.again_chosen() ? fmt::format("{} junction is the start reported", other)
                       : fmt::format("{} junction stands", first));
  return out;
}

}  // namespace tofcomp::cli
