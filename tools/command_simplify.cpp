// ddsimp simplify IN -o OUT: reads, simplifies with ddsimp::simplify, writes, reports.
#include "cli_support.h"
#include "commands.h"
#include "ddsimp/io/surface_io.h"
#include "simplify_args.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>

namespace ddsimp::cli {

namespace {

int run_simplify(const SimplifyArgs& args, const CLI::App& app) {
    Options options = simplify_options(args, app);
    io::check_output_path(args.output);
    const Surface input = read_input(args.input);
    require_fields(input, args.fields, args.input);

    Result result;
    double seconds = 0;
    {
        TerminalProgress progress("simplifying " + args.input);
        options.progress = progress.callback();
        const auto start = std::chrono::steady_clock::now();
        try {
            result = simplify(input, options);
        } catch (const InputError& e) {
            throw io::IoError(args.input + ": " + e.what());
        }
        seconds = seconds_since(start);
    }
    write_output(result.surface, args.output, io::WriteOptions{args.colour_by, args.meshopt});

    if (args.json)
        std::printf("%s\n", simplify_json(args, options, result, seconds).dump().c_str());
    else
        print_simplify_summary(args, options, result, seconds);
    return kExitOk;
}

} // namespace

Command add_simplify_command(CLI::App& app) {
    auto args = std::make_shared<SimplifyArgs>();
    CLI::App* sub = app.add_subcommand("simplify", "Reduce a surface, keeping its topology");
    add_simplify_options(*sub, *args);
    return {sub, [args, sub] { return run_simplify(*args, *sub); }};
}

} // namespace ddsimp::cli
