// The junction's dynamics re-checked once the model search has kept a term.
//
// Training may take the junction's rise P·R1 and time constant R1·C1 from the ranges
// (calibration/junction_dynamics.hpp) when they reject the case log's: a junction that heats
// more, or more slowly, after each power-on than the case log says moves H(t^j)θ after each
// power-on. An effect Eq. 8 lacks that also lives after each power-on (a warm-up, another
// thermal state, a bias with the heating rate) is explained there in part by such a junction, so
// the training's junction takes some of it in, and the search then sees, and names, what is
// left. Measured on the blind draws (docs/closing-the-loop.md, §5): the junction of a warm-up set
// taken from the ranges rose 5.5 K with 77 s where the true one rose 2.0 K with 22 s.
//
// So when training took the junction from the ranges and the search kept a term, training runs
// again with the case log's junction, the search again from it, and the start whose final model
// predicts held-out ranges better is kept: the mean held-out log-likelihood over the ranges both
// searches scored (a range is scored inside the other fold's junction range, which depends on
// the junction estimate), by the same folds. Where the search keeps nothing the training's
// junction stands as it is: the re-check never adds a term to data the search found complete.
//
// The other way round too: where training kept the case log's junction because the ranges'
// blocks did not reject it, although the ranges' answer has the higher posterior, and the search
// kept a term, training runs again with the ranges' answer and the better start is kept the same
// way. The blocks' t-test has little power where the junction's misfit lives: a few hundred
// ranges after each of a record's 4-7 power-ons, in as many of its blocks, so the others only add
// to its noise. Measured on a blind draw (seed 6602, set-0021-clean: a junction rising 5.1 K with
// 31 s where the case log's rose 1.15 K with 10.9 s), the ranges gained 37.3 nats, t 1.17 over
// blocks of 200, and the search named that misfit "warm-up after power-on" (t 3.10 over 2.91).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "calibration/model_search.hpp"
#include "calibration/trained_search.hpp"
#include "calibration/training.hpp"

namespace tofcomp::calibration {

// Whether training took the junction from the ranges: the re-check from the case log's then
// runs after the whole search (calibration/trained_search.cpp).
bool junction_may_be_rechecked(const Training& training);

// The junction the re-check trains again with: the case log's where training took the ranges',
// the ranges' untested answer where it is above the case log's; none where training's is the only
// one (the ranges' search did not run, or found nothing better).
std::optional<JunctionSource> junction_alternative(const Training& training);

// `settings` with the junction a re-check chose: trained again later (the structure's re-check,
// calibration/structure_recheck.hpp) it comes from the same source.
TrainSettings with_rechecked_junction(const TrainSettings& settings,
                                      const std::optional<JunctionRecheck>& recheck);

// The re-check above on `trained` (training with `settings` and the search from it with
// `options`); returns it unchanged, with no re-check, unless there is a junction_alternative and
// the search kept a term of its own. Never throws for the re-check's training or
// search: their error is kept in the re-check and the ranges' junction stands.
TrainedSearch recheck_junction(const MeasuredData& data, const TrainSettings& settings,
                               const ModelSearchOptions& options, TrainedSearch trained,
                               const TrainingProgress& progress = {});

}  // namespace tofcomp::calibration
