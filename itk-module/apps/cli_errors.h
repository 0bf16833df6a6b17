// Exit codes of the gdm command and the typed errors that map onto them.
#pragma once

#include <stdexcept>
#include <string>

namespace gdm_cli {

// Documented in --help and in README.md ("Command line: gdm").
enum ExitCode : int {
  exit_ok = 0,             // the model was built and written
  exit_internal = 1,       // an unexpected error (a bug: please report it)
  exit_usage = 2,          // bad usage: unknown option, bad value, seed outside the volume
  exit_input = 3,          // unreadable or invalid input (missing file, not 3D, corrupt header)
  exit_model_failed = 4,   // the model failed (leaked to the volume border, face limit, ...)
  exit_output = 5,         // the mesh or the report could not be written
};

// An error with the exit code it ends the program with.
class CliError : public std::runtime_error {
 public:
  CliError(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

struct UsageError : CliError {
  explicit UsageError(const std::string& m) : CliError(exit_usage, m) {}
};
struct InputError : CliError {
  explicit InputError(const std::string& m) : CliError(exit_input, m) {}
};
struct ModelError : CliError {
  explicit ModelError(const std::string& m) : CliError(exit_model_failed, m) {}
};
struct OutputError : CliError {
  explicit OutputError(const std::string& m) : CliError(exit_output, m) {}
};

}  // namespace gdm_cli
