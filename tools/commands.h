// The ddsimp subcommands: each adds itself to the CLI11 app and returns what runs it.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace ddsimp::cli {

// A subcommand and what runs it once parsed: returns the exit status, throws on errors (main.cpp
// turns them into one line and an exit status).
struct Command {
    CLI::App* app;
    std::function<int()> run;
};

Command add_simplify_command(CLI::App& app);
Command add_info_command(CLI::App& app);
Command add_compare_command(CLI::App& app);
Command add_isosurface_command(CLI::App& app);
#ifdef DDSIMP_HAVE_REMOTE
Command add_remote_command(CLI::App& app); // ddsimp remote upload|list|simplify|watch|set
#endif

} // namespace ddsimp::cli
