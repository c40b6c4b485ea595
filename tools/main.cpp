// ddsimp: the command line of the data-dependent surface simplifier.
//
// Exit status: 0 on success, 1 for an input or I/O error (missing, unreadable or malformed file,
// a field the file does not have, input the library rejects), 2 for a usage error (unknown
// option, bad value). Every error is one line on stderr starting with "ddsimp: ".
#include "cli_support.h"
#include "commands.h"
#include "ddsimp/io/surface_io.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <vector>

namespace {

int fail(int status, const std::string& message) {
    std::string line = message;
    for (char& c : line)
        if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "ddsimp: %s\n", line.c_str());
    return status;
}

} // namespace

int main(int argc, char** argv) {
    using namespace ddsimp::cli;
    CLI::App app{"ddsimp: data-dependent surface simplification (Frank & Lang)\n"
                 "Exit status: 0 success, 1 input or I/O error, 2 usage error."};
    app.require_subcommand(1);
    std::vector<Command> commands = {add_simplify_command(app), add_info_command(app),
                                     add_compare_command(app), add_isosurface_command(app)};
#ifdef DDSIMP_HAVE_REMOTE
    commands.push_back(add_remote_command(app));
#endif

    // CLI11 would only say "a subcommand is required" for a misspelt one.
    if (argc > 1 && argv[1][0] != '-') {
        bool known = false;
        for (const Command& c : commands) known = known || c.app->check_name(argv[1]);
        if (!known)
            return fail(kExitUsageError, std::string("unknown command '") + argv[1] +
                                             "' (commands: simplify, info, compare, isosurface" +
                                             (commands.size() > 4 ? ", remote)" : ")"));
    }

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) { // --help
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::string command = "ddsimp";
        for (const Command& c : commands)
            if (c.app->parsed()) command += " " + c.app->get_name();
        return fail(kExitUsageError, e.what() + (" (see " + command + " --help)"));
    }

    try {
        for (const Command& c : commands)
            if (c.app->parsed()) return c.run();
        return fail(kExitUsageError, "no command given (see ddsimp --help)");
    } catch (...) {
        const Failure f = failure_of(std::current_exception());
        return fail(f.status, f.message);
    }
}
