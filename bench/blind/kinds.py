"""The blind suite's vocabulary of effects: (parameter, covariate) labels, fixed, shared by
generate.py (which draws them) and score.py (which compares the detector's labels with them)."""

KINDS = [
    ("bias", "time"),
    ("bias", "time_since_power_on"),
    ("bias", "heating_rate"),
    ("bias", "ambient"),
    ("mode_offset", "junction_temperature"),
    ("spread", "junction_temperature"),
    ("weights", "junction_temperature"),
    ("weights", "time_since_power_on"),
    ("markov", "none"),
    ("extra_mode", "none"),
    ("outliers", "none"),
    ("thermal_state", "none"),
]
