// The structure re-checked after the search kept a term on the bias: see structure_recheck.hpp.
#include "calibration/structure_recheck.hpp"

#include <string>

#include "calibration/covariates.hpp"
#include "calibration/junction_recheck.hpp"
#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

const core::CandidateEvidence& chosen_candidate(const core::StructureChoice& choice) {
  return choice.candidates.at(static_cast<std::size_t>(choice.chosen));
}

// The same family, order and modes (a Fourier fundamental follows the junction's span, which the
// two choices may have seen differently).
bool same_structure(const core::StructureChoice& a, const core::StructureChoice& b) {
  const core::CandidateEvidence &x = chosen_candidate(a), &y = chosen_candidate(b);
  return x.family == y.family && x.order == y.order && x.modes == y.modes;
}

}  // namespace

std::vector<core::Term> kept_bias_terms(const ModelSearchResult& search) {
  std::vector<core::Term> out;
  for (std::size_t i = static_cast<std::size_t>(search.carried_from_training);
       i < search.kept.size(); ++i) {
    if (search.kept[i].parameter == core::Parameter::Bias) out.push_back(search.kept[i]);
  }
  return out;
}

TrainedSearch recheck_structure(const MeasuredData& data, const TrainSettings& settings,
                                const ModelSearchOptions& options, TrainedSearch trained,
                                const TrainingProgress& progress) {
  const std::optional<core::StructureChoice>& first = trained.training.structure;
  const std::vector<core::Term> bias_terms = kept_bias_terms(trained.search);
  const std::optional<core::ModelExtension>& extension = trained.search.calibration.extension;
  if (!first || bias_terms.empty() || !extension) return trained;
  StructureRecheck recheck;
  recheck.first = chosen_candidate(*first).name;
  recheck.first_modes = first->modes;
  recheck.bias_terms = bias_terms;
  recheck.kept_first = trained.search.kept;
  // Training again as the re-checked junction stands.
  TrainSettings again = with_rechecked_junction(settings, trained.junction_recheck);
  try {
    // The bias of the kept terms as fitted on all the data, at every range.
    const Eigen::VectorXd bias =
        extension->bias(covariate_table(data, trained.training.junction));
    const core::StructureChoice chosen =
        choose_structure_on(data, again, trained.training, bias,
                            progress_part(progress, 0.0, 0.3,
                                          "re-checking the structure without the kept bias: "));
    recheck.again = chosen_candidate(chosen).name;
    recheck.again_modes = chosen.modes;
    if (!same_structure(chosen, *first)) {
      again.structure_chosen = chosen;
      TrainedSearch at_it = train_and_search(
          data, again, options,
          progress_part(progress, 0.3, 0.7, "re-checking the structure at the new choice, "));
      recheck.searched_again = true;
      recheck.kept_again = at_it.search.kept;
      recheck.chosen = !kept_bias_terms(at_it.search).empty();
      if (recheck.chosen) {
        trained.training = std::move(at_it.training);
        trained.search = std::move(at_it.search);
      }
    }
  } catch (const core::Error& e) {
    recheck.error = e.what();
  }
  if (progress) progress(1.0, "re-checking the structure: done");
  trained.structure_recheck = std::move(recheck);
  return trained;
}

}  // namespace tofcomp::calibration
