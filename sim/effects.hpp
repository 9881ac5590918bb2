// Effects the paper's measurement model (Eq. 8) lacks, which a scenario can switch on so that
// the twin produces data with an undeclared effect (for `tofcomp diagnose`). Each is off unless
// its section is present in the scenario's `effects:`; docs/scenarios.md documents each.
#pragma once

#include <optional>

namespace tofcomp::sim {

// The lasing mode persists: after a pulse in mode i the next pulse stays in mode i with
// probability stay_probability, else it is drawn afresh from the weights (a Markov chain whose
// stationary law keeps the weights), instead of Eq. 8's independent Bernoulli draws.
struct ModePersistence {
  double stay_probability = 0.9;
};

// The modes' weights depend on the junction temperature: the log-odds of every mode against
// the first move by log_odds_per_c × (t − bias.reference_c).
struct TemperatureDependentWeights {
  double log_odds_per_c = 0.5;
};

// The spread of every mode grows with temperature: σ_i(t) = σ_i (1 + relative_per_c (t − ref)),
// floored at 10 % of σ_i.
struct TemperatureDependentSpread {
  double relative_per_c = 0.15;
};

// A fraction of the ranges are outliers: the true range plus a uniform error in ±spread_mm.
struct Outliers {
  double fraction = 0.01;
  double spread_mm = 100.0;
};

// The bias also depends on how fast the junction heats or cools: + mm_per_c_per_min × dt^j/dt.
struct HeatingHysteresis {
  double mm_per_c_per_min = 3.0;
};

// A slow drift of the range with time since the start, unrelated to temperature (ageing,
// mechanical creep): + mm_per_hour × t.
struct TimeDrift {
  double mm_per_hour = 0.3;
};

// A transient after each power-on that is not the junction's temperature (Eq. 3 models that):
// the laser driver and the receiver settle, + amplitude_mm × exp(−t_on / time_constant_s), t_on
// the time since the scanner was last switched on (since t = 0 when it starts on).
struct WarmUp {
  double amplitude_mm = 3.0;
  double time_constant_s = 300.0;
};

struct TwinEffects {
  std::optional<ModePersistence> mode_persistence;
  std::optional<TemperatureDependentWeights> temperature_dependent_weights;
  std::optional<TemperatureDependentSpread> temperature_dependent_spread;
  std::optional<Outliers> outliers;
  std::optional<HeatingHysteresis> heating_hysteresis;
  std::optional<TimeDrift> time_drift;
  std::optional<WarmUp> warm_up;

  bool any() const {
    return mode_persistence || temperature_dependent_weights || temperature_dependent_spread ||
           outliers || heating_hysteresis || time_drift || warm_up;
  }
};

}  // namespace tofcomp::sim
