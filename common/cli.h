// Command-line conventions shared by every syn-* tool (DESIGN.md,
// "Conventions"): `syn-<stage> INPUT... -o OUTPUT [--flags]`, `--help`,
// `--version`, `-v`; exit 0 ok, 1 bad data or failure, 2 bad usage.
//
// Include this only from stages/*/main.cpp: CLI11 is header-only here and
// costs seconds per translation unit.
#pragma once

#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/intermediate_file.h"
#include "common/text_encoding.h"
#include "common/version.h"

namespace syn {

// Flags every tool has.
struct CommonFlags {
  std::string output;
  bool verbose = false;
};

// Registers --version and -v; with `with_output`, the required -o OUTPUT.
inline void AddCommonFlags(CLI::App& app, CommonFlags& flags, bool with_output = true) {
  app.set_version_flag("--version", std::string(app.get_name()) + " " + kVersion);
  app.add_flag("-v,--verbose", flags.verbose, "Print resolved parameters and per-item detail on stderr");
  if (with_output) {
    app.add_option("-o,--output", flags.output, "Output file (written to a temporary name, then renamed)")
        ->required();
  }
}

// Parses the command line and runs `body`, translating every failure into
// one message on stderr and the documented exit code. This is the only place
// where exceptions become exit codes.
// What a loaded file needed forgiving or looks wrong in (Model::warnings()), one line each.
inline void PrintWarnings(const std::string& tool, const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings) std::cerr << tool << ": warning: " << Printable(warning) << "\n";
}

// How a loaded file was read (Model::notes()), printed with -v.
inline void PrintNotes(const std::string& tool, const std::vector<std::string>& notes, bool verbose) {
  if (!verbose) return;
  for (const std::string& note : notes) std::cerr << tool << ": " << Printable(note) << "\n";
}

// Throws UsageError with the options' own complaint. Called from a stage's `parameters` (below) as well
// as its body, so `--print-parameters` refuses exactly the values a run would, and syn-plan can check a
// manifest's values before make runs anything.
template <typename Options>
void RequireValid(const Options& options) {
  std::string problem;
  if (!options.IsValid(&problem)) throw UsageError(problem);
}

// `parameters` (optional) returns the canonical parameters of a run: what goes into the output's
// `parameters` attribute. With it the tool has `--print-parameters`: parse the other flags (inputs and
// -o not needed), check them (a `parameters` that throws UsageError refuses them: exit 2), print that
// JSON on stdout and exit. syn-plan learns every stage's
// parameter names and defaults this way, without linking stage code.
inline int RunTool(CLI::App& app, int argc, char** argv, const std::function<nlohmann::json()>& parameters,
                   const std::function<void()>& body) {
  const std::string tool = app.get_name();
  bool print_parameters = false;
  if (parameters) {
    app.add_flag("--print-parameters", print_parameters,
                 "Print the parameters these flags give (the output's `parameters` attribute) as JSON and exit");
    for (int i = 1; i < argc; ++i) {
      if (std::string(argv[i]) != "--print-parameters") continue;
      for (CLI::Option* option : app.get_options()) option->required(false);  // no inputs or -o needed
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& done) {  // --help, --version
    return app.exit(done);
  } catch (const CLI::ParseError& error) {
    app.exit(error);
    return 2;
  }
  try {
    if (print_parameters) {
      std::cout << CanonicalJson(parameters()) << "\n";
      return 0;
    }
    body();
    return 0;
  } catch (const UsageError& error) {
    std::cerr << tool << ": usage error: " << error.what() << "\nRun " << tool << " --help for usage.\n";
    return 2;
  } catch (const DataError& error) {
    std::cerr << tool << ": error: " << error.what() << "\n";
    return 1;
  } catch (const std::exception& error) {
    std::cerr << tool << ": internal error (please report): " << error.what() << "\n";
    return 1;
  }
}

inline int RunTool(CLI::App& app, int argc, char** argv, const std::function<void()>& body) {
  return RunTool(app, argc, argv, nullptr, body);
}

// A stage's parameters with the --floating-base it loaded the model with (segment, evaluate, simulate).
inline nlohmann::json WithFloatingBase(nlohmann::json parameters, const std::string& floating_base) {
  parameters["floating_base"] = floating_base;
  return parameters;
}

}  // namespace syn
