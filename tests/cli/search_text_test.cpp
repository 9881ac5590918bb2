// `tofcomp diagnose`'s table of a step's candidates (cli/search_format.hpp): each column starts
// where its heading does, whatever the length of the effects' names, so that a long name (a
// mode's offset on the time since power-on, 50 characters) never runs into the term beside it.
// A kept term judged again after a later step is said to be held or dropped, with its figures.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "calibration/model_search.hpp"
#include "cli/search_format.hpp"
#include "core/effect_grammar.hpp"

namespace tofcomp::cli {
namespace {

calibration::CandidateResult candidate(core::Parameter parameter, core::Covariate covariate,
                                       core::Form form, int mode, double gain) {
  calibration::CandidateResult r;
  r.term.parameter = parameter;
  r.term.covariate = covariate;
  r.term.form = form;
  r.term.mode = mode;
  r.term.time_constant_s = 240.0;
  r.held_out_gain = gain * 1000.0;
  r.gain_per_range = gain;
  r.t_statistic = 3.0;
  r.p_value = 0.01;
  return r;
}

// The lines of `text` from the one starting with `first` to the next blank or unindented one.
std::vector<std::string> table_after(const std::string& text, const std::string& first) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (inside && (line.empty() || line[0] != ' ')) break;
    if (inside) lines.push_back(line);
    if (line.rfind(first, 0) == 0) inside = true;
  }
  return lines;
}

TEST(SearchText, CandidateColumnsStartWhereTheirHeadingsDo) {
  calibration::SearchStep step;
  step.candidates.push_back(candidate(core::Parameter::ModeOffset,
                                      core::Covariate::TimeSincePowerOn, core::Form::Decay, 0,
                                      1.65e-2));
  step.candidates.push_back(
      candidate(core::Parameter::Bias, core::Covariate::Time, core::Form::Linear, -1, 1e-3));
  calibration::CandidateResult failed =
      candidate(core::Parameter::Spread, core::Covariate::JunctionTemperature,
                core::Form::Linear, -1, 0.0);
  failed.error = "singular";
  step.candidates.push_back(failed);
  calibration::ModelSearchResult search;
  search.steps.push_back(step);

  const std::string text = search_text(search, calibration::ModelSearchOptions{});
  const std::vector<std::string> table = table_after(text, "step 1 candidates");
  ASSERT_EQ(table.size(), 4u) << text;
  const std::string& heading = table[0];
  const std::size_t term_at = heading.find("term");
  const std::size_t gain_at = heading.find("gain/range");
  ASSERT_NE(term_at, std::string::npos);
  ASSERT_NE(gain_at, std::string::npos);
  for (std::size_t i = 1; i < table.size(); ++i) {
    const calibration::CandidateResult& r = step.candidates[i - 1];
    const std::string& row = table[i];
    const std::string effect = core::effect_name(r.term.label());
    const std::string term = r.term.describe();
    EXPECT_EQ(row.find(effect), 2u) << row;
    EXPECT_EQ(row.compare(term_at, term.size(), term), 0) << "term not under its heading:\n"
                                                          << heading << "\n" << row;
    EXPECT_EQ(row.substr(term_at - 2, 2), "  ") << "the effect runs into the term:\n" << row;
    if (r.ok()) {
      // The numbers right-aligned under theirs: the gain ends where its heading does.
      EXPECT_EQ(row[gain_at + std::string("gain/range").size()], ' ') << row;
      EXPECT_NE(row[gain_at + std::string("gain/range").size() - 1], ' ') << row;
    } else {
      EXPECT_NE(row.find("not fitted: singular", term_at), std::string::npos) << row;
    }
  }
  // The long name is why the columns move: it must be among the rows.
  EXPECT_GT(core::effect_name(step.candidates[0].term.label()).size(), 44u);
}

TEST(SearchText, SaysHowAKeptTermFaredWhenJudgedAgain) {
  calibration::SearchStep warm_up, state;
  warm_up.candidates.push_back(candidate(core::Parameter::Bias, core::Covariate::TimeSincePowerOn,
                                         core::Form::Decay, -1, 1e-2));
  warm_up.kept = true;
  warm_up.critical_t = 3.1;
  warm_up.judged_again_after_step = 2;
  warm_up.gain_beside_later = 12.5;
  warm_up.t_beside_later = 0.75;
  warm_up.p_beside_later = 0.23;
  warm_up.dropped = true;
  state.candidates.push_back(
      candidate(core::Parameter::Bias, core::Covariate::JunctionLag, core::Form::Linear, -1, 2e-2));
  state.kept = true;
  calibration::ModelSearchResult search;
  search.steps = {warm_up, state};
  search.kept = {state.candidates.front().term};

  const std::string text = search_text(search, calibration::ModelSearchOptions{});
  const std::size_t step1 = text.find("step 1: named");
  const std::size_t step2 = text.find("step 2: named");
  const std::size_t dropped =
      text.find("judged again after step 2: beside the later terms, keeping it gains 12.5 nats, "
                "t 0.75 (p 0.23) above 0.05: dropped");
  ASSERT_NE(dropped, std::string::npos) << text;
  EXPECT_TRUE(step1 < dropped && dropped < step2) << text;  // under the step that kept it
  EXPECT_EQ(text.find("judged again", dropped + 1), std::string::npos) << text;
  EXPECT_NE(text.find("verdict: the model lacks another thermal state"), std::string::npos)
      << text;

  const nlohmann::json json = to_json(search, calibration::ModelSearchOptions{});
  const nlohmann::json& first = json.at("steps").at(0).at("judged_again");
  EXPECT_EQ(first.at("after_step"), 2);
  EXPECT_DOUBLE_EQ(first.at("held_out_gain").get<double>(), 12.5);
  EXPECT_DOUBLE_EQ(first.at("t").get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(first.at("p").get<double>(), 0.23);
  EXPECT_TRUE(first.at("dropped").get<bool>());
  EXPECT_TRUE(json.at("steps").at(1).at("judged_again").is_null());
  EXPECT_EQ(json.at("kept").size(), 1u);

  // Judged again and still passing: said to be held.
  search.steps[0].dropped = false;
  search.steps[0].t_beside_later = 4.25;
  search.steps[0].p_beside_later = 1.5e-5;
  search.kept.insert(search.kept.begin(), warm_up.candidates.front().term);
  const std::string held = search_text(search, calibration::ModelSearchOptions{});
  EXPECT_NE(held.find("keeping it gains 12.5 nats, t 4.25 (p 1.5e-05) within 0.05: held"), std::string::npos)
      << held;
}

}  // namespace
}  // namespace tofcomp::cli
