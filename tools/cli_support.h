// Small pieces shared by the ddsimp subcommands: errors, field checks, progress on a terminal.
#pragma once

#include "ddsimp/ddsimp.h"
#include "ddsimp/io/surface_io.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <exception>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ddsimp::cli {

// A command line that parses but makes no sense ("--keep 2"); exit status 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Exit statuses of the ddsimp command.
inline constexpr int kExitOk = 0;
inline constexpr int kExitInputError = 1; // missing, malformed or unsuitable input; I/O failure
inline constexpr int kExitUsageError = 2; // the command line itself is wrong

// The exit status and message for an exception a command let through: a UsageError is 2; input,
// I/O and memory errors are 1, and so is anything else, as an internal error.
struct Failure {
    int status = kExitInputError;
    std::string message;
};
Failure failure_of(std::exception_ptr error);

std::string join(const std::vector<std::string>& items, const std::string& separator = ", ");

// "V(3), Temp, Pres" — the surface's fields, for messages.
std::string describe_fields(const Surface& surface);

// Throws io::IoError("<path> has no field 'X' (fields: ...)") for the first name not in `surface`.
void require_fields(const Surface& surface, const std::vector<std::string>& names,
                    const std::string& path);

// Prints "label  42%" on stderr while a long run works, but only if stderr is a terminal.
class TerminalProgress {
public:
    explicit TerminalProgress(std::string label);
    ~TerminalProgress(); // clears the line
    TerminalProgress(const TerminalProgress&) = delete;
    TerminalProgress& operator=(const TerminalProgress&) = delete;

    // A callback for ddsimp::Options::progress (never cancels); empty if stderr is no terminal.
    std::function<bool(double)> callback();

private:
    std::string label_;
    bool active_;
    int shown_ = -1;
};

// io::read_surface and io::write_surface, each note of the reader (what it triangulated, set
// aside or read of a file cut short) or of the writer (the fields it cannot hold) printed on
// stderr as "ddsimp: note: PATH: ...".
Surface read_input(const std::string& path);
void write_output(const Surface& surface, const std::string& path,
                  const io::WriteOptions& options = {});

// What validate() repaired, as the "repairs" object of --json outputs.
nlohmann::json repairs_json(const RepairReport& repairs);

// Seconds elapsed since `start`, by the steady clock.
double seconds_since(std::chrono::steady_clock::time_point start);

} // namespace ddsimp::cli
