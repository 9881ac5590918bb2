#include "cli/recording_batch_format.hpp"

#include <algorithm>
#include <fmt/format.h>

#include "cli/report_format.hpp"
#include "cli/junction_recheck_format.hpp"
#include "cli/structure_recheck_format.hpp"
#include "cli/search_format.hpp"

namespace tofcomp::cli {
namespace {

constexpr const char* kCalibrated = "calibrated";
constexpr const char* kNotDiagnosed = "calibrated, not diagnosed";
constexpr const char* kFailed = "failed";

std::string status_of(const calibration::RecordingOutcome& outcome) {
  if (!outcome.calibrated()) return kFailed;
  return outcome.search ? kCalibrated : kNotDiagnosed;
}

// "polynomial(6), 3 modes" from the training's calibration JSON.
std::string structure_of(const nlohmann::json& calibration) {
  return fmt::format("{}, {} modes", calibration.at("basis").get<std::string>(),
                     calibration.at("modes").size());
}

}  // namespace

nlohmann::json recording_json(const calibration::RecordingOutcome& outcome,
                              const calibration::ModelSearchOptions& options,
                              const std::string& calibration_file) {
  nlohmann::json j = {{"recording", outcome.recording.string()},
                      {"status", status_of(outcome)},
                      {"error", outcome.error},
                      {"warnings", outcome.warnings},
                      {"seconds", outcome.seconds},
                      {"calibration_file", outcome.calibrated() ? calibration_file : ""},
                      {"training", nullptr},
                      {"search", nullptr},
                      {"search_error", outcome.search_error},
                      {"named", nullptr},
                      {"junction_recheck", outcome.junction_recheck
                                               ? to_json(*outcome.junction_recheck)
                                               : nlohmann::json(nullptr)},
                      {"structure_recheck", outcome.structure_recheck
                                                ? to_json(*outcome.structure_recheck)
                                                : nlohmann::json(nullptr)}};
  if (outcome.training) {
    j["training"] = training_json(*outcome.training);
    const auto& trained = outcome.training->calibration.model.trained_junction_c;
    j["training"]["trained_junction_c"] =
        trained ? nlohmann::json{trained->min_c, trained->max_c} : nlohmann::json(nullptr);
  }
  if (outcome.search) {
    j["search"] = to_json(*outcome.search, options);
    j["named"] = kept_names(*outcome.search);
  }
  return j;
}

nlohmann::json recording_row(const nlohmann::json& recording) {
  nlohmann::json row = {{"recording", recording.at("recording")},
                        {"status", recording.at("status")},
                        {"error", recording.at("error").get<std::string>().empty()
                                      ? recording.at("search_error")
                                      : recording.at("error")},
                        {"seconds", recording.at("seconds")},
                        {"calibration_file", recording.at("calibration_file")},
                        {"ranges", nullptr},
                        {"junction_c", nullptr},
                        {"structure", nullptr},
                        {"junction_from", nullptr},
                        {"named", recording.at("named")},
                        {"mae_over_cramer_rao", nullptr}};
  const nlohmann::json& training = recording.at("training");
  if (!training.is_null()) {
    const nlohmann::json& calibration = training.at("calibration");
    row["ranges"] = calibration.at("samples");
    row["junction_c"] = training.at("trained_junction_c");
    row["structure"] = structure_of(calibration);
    const nlohmann::json& junction = training.at("choices").at("junction_dynamics");
    row["junction_from"] =
        !junction.is_null() && junction.value("replaced", false) ? "ranges" : "case log";
  }
  const nlohmann::json& search = recording.at("search");
  if (!search.is_null()) row["mae_over_cramer_rao"] = search.at("mae_over_cramer_rao").at("final");
  return row;
}

std::string batch_table_text(const std::vector<nlohmann::json>& rows,
                             const std::vector<Eigen::Index>& windows) {
  std::size_t name_width = std::string("recording").size();
  std::size_t structure_width = std::string("structure").size();
  std::size_t named_width = std::string("named").size();
  for (const auto& r : rows) {
    name_width = std::max(name_width, r.at("recording").get<std::string>().size());
    if (!r.at("structure").is_null()) {
      structure_width = std::max(structure_width, r.at("structure").get<std::string>().size());
    }
    if (!r.at("named").is_null()) {
      named_width = std::max(named_width, r.at("named").get<std::string>().size());
    }
  }
  std::string window_list;
  for (const Eigen::Index w : windows) window_list += (window_list.empty() ? "" : "/") + std::to_string(w);
  // The deployed model's held-out d̂ error over the Cramér–Rao bound, per window length.
  const std::string ratio_header = "MAE/CRB at " + window_list;
  std::string out = fmt::format("{:<{}}  {:>7}  {:<13}  {:<{}}  {:<8}  {:<{}}  {:<{}}  {:>8}\n",
                                "recording", name_width, "ranges", "junction °C", "structure",
                                structure_width, "junction", "named", named_width, ratio_header,
                                ratio_header.size(), "seconds");
  int failed = 0;
  for (const auto& r : rows) {
    const std::string name = r.at("recording").get<std::string>();
    if (r.at("status") == kFailed) {
      ++failed;
      out += fmt::format("{:<{}}  failed: {}\n", name, name_width,
                         r.at("error").get<std::string>());
      continue;
    }
    const auto& span = r.at("junction_c");
    const std::string junction =
        span.is_null() ? "-" : fmt::format("{:.1f}–{:.1f}", span[0].get<double>(), span[1].get<double>());
    std::string ratios;
    const auto& ratio = r.at("mae_over_cramer_rao");
    for (const Eigen::Index w : windows) {
      const std::string key = std::to_string(w);
      ratios += (ratios.empty() ? "" : " ");
      ratios += ratio.is_null() || !ratio.contains(key) ? "-" : fmt::format("{:.2f}", ratio.at(key).get<double>());
    }
    out += fmt::format("{:<{}}  {:>7}  {:<13}  {:<{}}  {:<8}  {:<{}}  {:<{}}  {:>8.1f}\n", name,
                       name_width, r.at("ranges").get<long>(), junction,
                       r.at("structure").get<std::string>(), structure_width,
                       r.at("junction_from").get<std::string>(),
                       r.at("named").is_null() ? "-" : r.at("named").get<std::string>(), named_width,
                       ratios, ratio_header.size(), r.at("seconds").get<double>());
    if (r.at("status") == kNotDiagnosed) {
      out += fmt::format("{:<{}}  not diagnosed: {}\n", "", name_width, r.at("error").get<std::string>());
    }
  }
  out += fmt::format("{} recordings: {} calibrated, {} failed\n", rows.size(),
                     rows.size() - static_cast<std::size_t>(failed), failed);
  return out;
}

}  // namespace tofcomp::cli
