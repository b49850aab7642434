// Headless sub-commands of the plimsoll executable. Each adds itself to the root CLI11 app;
// when its sub-command is parsed, it stores in `selected` the function that runs it and returns
// the process exit code. Errors go to stderr, results to stdout.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace plimsoll::cli {

using CommandRunner = std::function<int()>;

void addValidateCommand(CLI::App& root, CommandRunner& selected);
void addBakeCommand(CLI::App& root, CommandRunner& selected);
void addMassPropsCommand(CLI::App& root, CommandRunner& selected);
void addSamplesCommand(CLI::App& root, CommandRunner& selected);
void addBenchCommand(CLI::App& root, CommandRunner& selected);
void addBuoyancyCommand(CLI::App& root, CommandRunner& selected);
void addSimulateCommand(CLI::App& root, CommandRunner& selected);
void addGraphCommand(CLI::App& root, CommandRunner& selected);
void addAtlasCommand(CLI::App& root, CommandRunner& selected);
void addExportCommand(CLI::App& root, CommandRunner& selected);
void addEditCommand(CLI::App& root, CommandRunner& selected);
void addRenderCommand(CLI::App& root, CommandRunner& selected);
void addHydrostaticsCommand(CLI::App& root, CommandRunner& selected);
void addHydroCommand(CLI::App& root, CommandRunner& selected);

/// Exit codes shared by all sub-commands.
enum ExitCode : int { kExitOk = 0, kExitFailure = 1, kExitUsage = 2 };

}  // namespace plimsoll::cli
