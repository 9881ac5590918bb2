// The structure of Eq. 8 re-checked once the model search has kept a term on the bias.
//
// Training chooses the basis and the number of modes (§7, core/structure_search.hpp) on the
// ranges as they come. An effect Eq. 8 lacks that moves the bias (an ambient's, a drift's, a
// warm-up's) is then explained in part by the structure: a higher order follows the effect where
// it correlates with the junction temperature, one more mode takes in the spread it adds to the
// residuals. The search then adds the effect's term, but the structure that took it in stays, and
// d̂ pays for it. Measured on a blind draw (docs/closing-the-loop.md §5): a bias of 1.5 mm/°C of
// the ambient trained polynomial(6), 4 modes, where the same record without it trains
// polynomial(2), 3 modes; with the ambient term kept, d̂'s held-out error at window 800 was
// 0.142 mm, 4 × the Cramér–Rao bound, against 0.057 mm without the effect.
//
// So when the search kept a term on the bias, the structure is chosen again by the same search on
// the ranges less those terms' bias as fitted, y − d − Σ γ_t f_t(c_k): what §7 chooses when the
// effect is declared. When that choice differs, training runs at it (on the ranges as they are;
// the choice's evidence kept) and the model search from it, and their result replaces the first
// when that search keeps a term on the bias too (the premise of the choice); otherwise the first
// stands. The re-check runs only after a kept term, so it never adds one to data the search found
// complete, and the second search holds its own family-wise level.
#pragma once

#include <vector>

#include "calibration/model_search.hpp"
#include "calibration/trained_search.hpp"
#include "calibration/training.hpp"

namespace tofcomp::calibration {

// The kept terms on the bias that the search added (the training's carried terms are not).
std::vector<core::Term> kept_bias_terms(const ModelSearchResult& search);

// The re-check above on `trained` (training with `settings`, possibly re-checked by
// recheck_junction, and the search from it with `options`: whole, or paused after its first term
// on the bias by search_and_recheck, calibration/trained_search.hpp); returns it unchanged, with no
// re-check, unless training chose the structure and the search kept a term on the bias. Never
// throws for the re-check's choice, training or search: their error is kept in the re-check and
// the first structure stands.
TrainedSearch recheck_structure(const MeasuredData& data, const TrainSettings& settings,
                                const ModelSearchOptions& options, TrainedSearch trained,
                                const TrainingProgress& progress = {});

}  // namespace tofcomp::calibration
