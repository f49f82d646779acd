/// @brief The subcommands of `cvc`, each defined in its own <name>_command.cpp.
#pragma once

namespace CLI {
class App;
}

namespace app {

/// Each adds one subcommand (its options and its callback) to the program.
void addRenderCommand(CLI::App& program);
void addPhantomCommand(CLI::App& program);
void addInfoCommand(CLI::App& program);
void addBakeCommand(CLI::App& program);
void addColonCommand(CLI::App& program);
void addPolypCheckCommand(CLI::App& program);
void addInsertPolypCommand(CLI::App& program);
void addMeasureCommand(CLI::App& program);
void addCoverageCommand(CLI::App& program);
void addCandidatesCommand(CLI::App& program);

}  // namespace app
