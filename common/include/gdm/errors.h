// Typed exceptions thrown by the gdm core. Every message names the problem.
#pragma once

#include <stdexcept>
#include <string>

namespace gdm {

// Base of all gdm errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An option out of its range (negative weight, NaN threshold, ...).
class InvalidOption : public Error {
 public:
  using Error::Error;
};

// A volume that cannot be used (zero or NaN spacing, empty, constant, ...).
class InvalidVolume : public Error {
 public:
  using Error::Error;
};

// A seed that cannot be used (outside the volume, open, non-manifold, ...).
class InvalidSeed : public Error {
 public:
  using Error::Error;
};

// A file that cannot be read or contradicts itself (empty, truncated, counts
// or indices out of range, non-finite coordinates, ...).
class InvalidInput : public Error {
 public:
  using Error::Error;
};

}  // namespace gdm
