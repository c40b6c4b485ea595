#include "cli_support.h"

#include "ddsimp/io/surface_io.h"

#include <cstdio>
#include <unistd.h>

namespace ddsimp::cli {

Failure failure_of(std::exception_ptr error) {
    try {
        std::rethrow_exception(error);
    } catch (const UsageError& e) {
        return {kExitUsageError, e.what()};
    } catch (const io::IoError& e) {
        return {kExitInputError, e.what()};
    } catch (const InputError& e) {
        return {kExitInputError, e.what()};
    } catch (const std::bad_alloc&) {
        return {kExitInputError, "out of memory"};
    } catch (const std::exception& e) {
        return {kExitInputError, std::string("internal error: ") + e.what()};
    } catch (...) {
        return {kExitInputError, "internal error: an unknown exception"};
    }
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
    std::string out;
    for (const std::string& item : items) {
        if (!out.empty()) out += separator;
        out += item;
    }
    return out;
}

std::string describe_fields(const Surface& surface) {
    std::vector<std::string> names;
    for (const Field& f : surface.fields)
        names.push_back(f.components == 1 ? f.name
                                          : f.name + "(" + std::to_string(f.components) + ")");
    return names.empty() ? "none" : join(names);
}

void require_fields(const Surface& surface, const std::vector<std::string>& names,
                    const std::string& path) {
    for (const std::string& name : names)
        if (surface.find_field(name) == nullptr)
            throw io::IoError(path + " has no field '" + name +
                              "' (fields: " + describe_fields(surface) + ")");
}

TerminalProgress::TerminalProgress(std::string label)
    : label_(std::move(label)), active_(isatty(STDERR_FILENO) == 1) {}

TerminalProgress::~TerminalProgress() {
    if (active_ && shown_ >= 0) std::fprintf(stderr, "\r\033[K");
}

std::function<bool(double)> TerminalProgress::callback() {
    if (!active_) return {};
    return [this](double fraction) {
        const int percent = int(fraction * 100.0);
        if (percent != shown_) {
            shown_ = percent;
            std::fprintf(stderr, "\r%s %3d%%", label_.c_str(), percent);
            std::fflush(stderr);
        }
        return true;
    };
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {
void print_notes(const std::string& path, const io::Notes& notes) {
    for (const std::string& note : notes)
        std::fprintf(stderr, "ddsimp: note: %s: %s\n", path.c_str(), note.c_str());
}
} // namespace

Surface read_input(const std::string& path) {
    io::Notes notes;
    Surface surface = io::read_surface(path, &notes);
    print_notes(path, notes);
    return surface;
}

void write_output(const Surface& surface, const std::string& path,
                  const io::WriteOptions& options) {
    io::Notes notes;
    io::write_surface(surface, path, options, &notes);
    print_notes(path, notes);
}

nlohmann::json repairs_json(const RepairReport& r) {
    return {{"degenerate_triangles_dropped", r.degenerate_triangles_dropped},
            {"duplicate_triangles_dropped", r.duplicate_triangles_dropped},
            {"triangles_flipped", r.triangles_flipped},
            {"unused_vertices", r.unused_vertices}};
}

} // namespace ddsimp::cli
