// Typed exceptions thrown by the gdm core. Every message names the problem.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace gdm {

// Base of all gdm errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An option out of its range (negative weight, NaN threshold, ...). When the
// option is one of the catalogue's (option_catalogue.h), option() names it so
// a front end can say it in its own spelling (--lod-tolerance, ...).
class InvalidOption : public Error {
 public:
  using Error::Error;
  InvalidOption(std::string option, const std::string& message) : Error(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
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
