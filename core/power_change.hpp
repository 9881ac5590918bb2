// A switch of the laser's supply: the heat input u of the thermal network (Eq. 4) steps to its
// rated value (on) or to zero (off). One event type for the measured data, the CSV and the twin.
#pragma once

namespace tofcomp::core {

struct PowerChange {
  double time_s = 0.0;
  bool on = true;

  bool operator==(const PowerChange&) const = default;
};

}  // namespace tofcomp::core
