// Errors raised by the estimation core. Every failure of core/ is one of these, with a message
// that names what was wrong; no function of core/ returns a NaN in place of an error.
#pragma once

#include <stdexcept>
#include <string>

namespace tofcomp::core {

// Base of every error tofcomp raises on purpose.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// The caller passed something the mathematics cannot take: mismatched lengths, NaN or Inf,
// too few samples, an order out of range.
class InvalidInput : public Error {
 public:
  explicit InvalidInput(const std::string& what) : Error(what) {}
};

// The data were well formed but the problem they pose has no unique answer: a singular normal
// matrix (too few distinct temperatures for the basis), a mixture mode left without samples,
// zero variance.
class NumericalError : public Error {
 public:
  explicit NumericalError(const std::string& what) : Error(what) {}
};

// EM emptied a mixture mode: its weight fell under the fit's minimum, so the data do not show
// as many modes as were fitted. mode(): the emptied mode, 0-based in the fit's order.
class EmptiedModeError : public NumericalError {
 public:
  EmptiedModeError(const std::string& what, int mode) : NumericalError(what), mode_(mode) {}
  int mode() const { return mode_; }

 private:
  int mode_;
};

}  // namespace tofcomp::core
