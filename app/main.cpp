/// @brief `cvc`: the conformal-vc command-line program. Parses arguments, runs one subcommand,
/// and turns any error into one line on stderr and a non-zero exit.
#include <csignal>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "distribution/mpi_session.h"
#include "engine/sequence/frame_sequence.h"

int main(int argc, char** argv) {
    // A file-size limit (ulimit -f) would otherwise kill the process with SIGXFSZ mid-write;
    // ignored, the write fails with EFBIG and is reported like a full disk: one message naming
    // the file, the finished frames kept for --resume.
    std::signal(SIGXFSZ, SIG_IGN);
    // Under mpirun, MPI starts before anything else (and sets lavapipe's threads per rank).
    const distribution::MpiSession mpi(&argc, &argv);
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
    app::addCandidatesCommand(program);

    try {
        // Only the display render, coverage and the polyp check share their work between
        // ranks; any other command would run the same job N times over the same files.
        const std::string command = argc >= 2 ? argv[1] : "";
        if (mpi.isShared() && command != "render" && command != "coverage" && command != "polyp-check") {
            throw std::invalid_argument("under mpirun only `cvc render --display`, `cvc coverage` and `cvc polyp-check` "
                                        "share their work between ranks; run other commands as one process");
        }
        program.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version are "errors" with exit code 0: CLI11 prints them. A real parse
        // error is one line like every other error, naming the option.
        if (e.get_exit_code() == 0) return program.exit(e);
        std::cerr << "cvc: error: " << e.what() << " (--help lists the options)\n";
        return e.get_exit_code();
    } catch (const engine::SequenceCancelled&) {
        std::cerr << "cvc: interrupted; the finished frames are kept (continue with --resume)\n";
        if (mpi.isShared()) mpi.abort(130);
        return 130;
    } catch (const std::exception& e) {
        // One rank's error stops the whole job: the others would wait for it for ever.
        if (mpi.isShared()) {
            std::cerr << "cvc: error on rank " << mpi.rank() << " of " << mpi.ranks() << ": " << e.what() << '\n';
            mpi.abort(1);
        }
        std::cerr << "cvc: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
