// Errors that leave the engine with a defined exit code (see docs/cli.md).
#pragma once
#include <stdexcept>
#include <string>

namespace tsubu {

// Where a value came from: its file and line, or its --set ("--set key=value", line 1), and
// its key; kept for checks made after loading (CSV rows, particle overlaps, the sizes).
struct SourceLocation {
  std::string file;
  long line = 0;
  std::string key;
};

// Bad input: "file:line: key: what is wrong and what is allowed". Exit code 2.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, long line, const std::string& key, const std::string& what)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + (key.empty() ? "" : key + ": ") + what) {}
  InputError(const SourceLocation& at, const std::string& what) : InputError(at.file, at.line, at.key, what) {}
};

// A mistake on the command line or in the choice of output folder that has no file:line
// (an output folder that holds another run or is in use). Exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An output file could not be written (disk full, quota, I/O error): the run stops, its
// last good checkpoint stays. Exit code 5.
class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The simulation became unphysical (NaN, runaway overlap, particle lost). Exit code 3.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A particle that the drift of a fixed step took out of the box, or made not finite
// (drift_to_step_end): the step ends there, before its evaluation.
class ParticleLost : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

// In a run split among processes, another process lost a particle in this step's drift
// (ParticleLost): every process ends the step where it learns of it, in the step's first
// exchange, so that the failing state gathered from all of them is one process's.
class StepAbandoned : public std::runtime_error {
 public:
  StepAbandoned() : std::runtime_error("another process lost a particle in this step's drift") {}
};

}  // namespace tsubu
