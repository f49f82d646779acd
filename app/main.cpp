/// @brief `cvc`: the conformal-vc command-line program. Parses arguments, runs one subcommand,
/// and turns any error into one line on stderr and a non-zero exit.
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "engine/display/frame_sequence.h"

int main(int argc, char** argv) {
    CLI::App program{"conformal-vc: virtual colonoscopy rendering for partially-immersive displays"};
    program.require_subcommand(1);
    program.set_version_flag("--version", "conformal-vc 0.1.0");

    app::addRenderCommand(program);
    app::addPhantomCommand(program);
    app::addInfoCommand(program);
    app::addBakeCommand(program);
    app::addColonCommand(program);
    app::addPolypCheckCommand(program);
    app::addInsertPolypCommand(program);
    app::addMeasureCommand(program);
    app::addCoverageCommand(program);

    try {
        program.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return program.exit(e);
    } catch (const engine::SequenceCancelled&) {
        std::cerr << "cvc: interrupted; the finished frames are kept (continue with --resume)\n";
        return 130;
    } catch (const std::exception& e) {
        std::cerr << "cvc: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
