#pragma once
#include <stdexcept>
#include <string>

namespace fscil {

// How fscil-bench ends. Decided here, from the kind of error, and only here; the command line
// prints an error's first line as `fscil-bench: error: ...` and exits with its status.
namespace exit_status {
constexpr int success = 0;
// A file, data, a value or a state the command cannot use (the message names which), a run that
// diverged or failed, a check that found drift; also errors of the libraries below us.
constexpr int bad_input = 1;
// The command line itself, or the options of a --config file: an unknown option, a malformed or
// out-of-range value, a missing or contradictory option.
constexpr int usage = 2;
// Stopped by a signal (SIGINT 130, SIGTERM 143): 128 + the signal, as a shell reports it.
constexpr int stopped_by(int signal) { return 128 + signal; }
}  // namespace exit_status

// The one error base: every error the harness raises is an Error, carrying its exit status.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, int status = exit_status::bad_input)
      : std::runtime_error(message), status_(status) {}
  int status() const { return status_; }

 private:
  int status_;
};

// The kinds, by floor; each names the file, field or option and what was expected.
// Bad dataset input: missing or malformed files, wrong shapes, bad values.
struct DatasetError : Error {
  explicit DatasetError(const std::string& message) : Error(message) {}
};
// Bad protocol set-ups: impossible session plans, malformed parameters, too few samples.
struct ProtocolError : Error {
  explicit ProtocolError(const std::string& message) : Error(message) {}
};
// Bad method requests and impossible method states.
struct MethodError : Error {
  explicit MethodError(const std::string& message) : Error(message) {}
};
// Unreadable or inconsistent result files and unwritable reports.
struct ReportError : Error {
  explicit ReportError(const std::string& message) : Error(message) {}
};
// A file that cannot be read, written or replaced; names the file.
struct FileError : Error {
  explicit FileError(const std::string& message) : Error(message) {}
};
// A malformed command line (exit_status::usage).
struct CliError : Error {
  explicit CliError(const std::string& message) : Error(message, exit_status::usage) {}
};

}  // namespace fscil
