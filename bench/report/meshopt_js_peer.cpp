#include "meshopt_js_peer.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

extern char** environ;

namespace ddsimp::report {

namespace {

namespace fs = std::filesystem;

// One continuous field as meshopt's attributes: value = (field value - component minimum) / range.
struct Scaled {
    size_t field = 0;
    std::vector<float> minimum;
    double range = 1;
};

// The range `ddsimp compare` divides a field's error by: the diagonal of its components' bounding
// box (a scalar's range), 1 for a constant field.
Scaled scaling_of(const Surface& input, size_t index) {
    const Field& f = input.fields[index];
    Scaled s{index, std::vector<float>(f.components, INFINITY), 1};
    std::vector<float> maximum(f.components, -INFINITY);
    for (size_t v = 0; v < input.vertex_count(); ++v)
        for (int c = 0; c < f.components; ++c) {
            const float x = f.values[v * f.components + c];
            s.minimum[c] = std::min(s.minimum[c], x);
            maximum[c] = std::max(maximum[c], x);
        }
    double sum = 0;
    for (int c = 0; c < f.components; ++c)
        sum += double(maximum[c] - s.minimum[c]) * double(maximum[c] - s.minimum[c]);
    if (sum > 0) s.range = std::sqrt(sum);
    return s;
}

template <class T> void write_array(std::ofstream& out, const std::vector<T>& values) {
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * 4));
}

template <class T> std::vector<T> read_array(std::ifstream& in, size_t count, const fs::path& p) {
    std::vector<T> values(count);
    if (!in.read(reinterpret_cast<char*>(values.data()), std::streamsize(count * sizeof(T))))
        throw std::runtime_error(p.string() + ": cut short");
    return values;
}

std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
    return text;
}

// A private directory for the exchange files, removed on every way out.
struct TemporaryDirectory {
    fs::path path;
    TemporaryDirectory() {
        std::string pattern = (fs::temp_directory_path() / "ddsimp-meshopt-XXXXXX").string();
        if (!mkdtemp(pattern.data()))
            throw std::runtime_error("cannot make a temporary directory: " +
                                     std::string(std::strerror(errno)));
        path = pattern;
    }
    ~TemporaryDirectory() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

// Runs `node args...` with stdout and stderr into `log`; its exit status (-signal if killed).
int run_node(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<char*> argv;
    std::string node = "node";
    argv.push_back(node.data());
    std::vector<std::string> copies = args;
    for (std::string& a : copies) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, "node", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0)
        throw std::runtime_error("cannot run node (" + std::string(std::strerror(spawned)) +
                                 "): install Debian's nodejs");
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            throw std::runtime_error("waitpid: " + std::string(std::strerror(errno)));
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

} // namespace

PeerOutput run_meshopt_js(const Surface& input, const PeerRequest& request, MeshoptJsMode mode) {
    std::vector<Scaled> scaled;
    size_t attributes = 0;
    for (size_t f = 0; f < input.fields.size(); ++f)
        if (input.fields[f].kind == FieldKind::Continuous) {
            scaled.push_back(scaling_of(input, f));
            attributes += size_t(input.fields[f].components);
        }
    if (attributes > 32)
        throw std::runtime_error("meshoptimizer weighs at most 32 attributes per vertex, the "
                                 "surface has " +
                                 std::to_string(attributes));
    const size_t n = input.vertex_count();
    std::vector<float> values(n * attributes);
    for (size_t v = 0, at = 0; v < n; ++v)
        for (const Scaled& s : scaled) {
            const Field& f = input.fields[s.field];
            for (int c = 0; c < f.components; ++c)
                values[at++] = float((f.values[v * f.components + c] - s.minimum[c]) / s.range);
        }

    TemporaryDirectory dir;
    const fs::path in_path = dir.path / "in.bin", out_path = dir.path / "out.bin";
    {
        std::ofstream out(in_path, std::ios::binary);
        const uint32_t header[3] = {uint32_t(n), uint32_t(input.triangles.size()),
                                    uint32_t(attributes)};
        out.write(reinterpret_cast<const char*>(header), sizeof header);
        write_array(out, input.positions);
        write_array(out, input.triangles);
        write_array(out, values);
        if (!out) throw std::runtime_error("cannot write " + in_path.string());
    }
    const bool update = mode == MeshoptJsMode::Update;
    const int status = run_node(
        {DDSIMP_REPORT_MESHOPT_JS, update ? "update" : "attributes", std::to_string(request.weight),
         std::to_string(request.target_triangles * 3), in_path.string(), out_path.string()},
        dir.path / "log.txt");
    if (status != 0) {
        std::string log = read_text(dir.path / "log.txt");
        if (log.empty()) log = "node exited with status " + std::to_string(status);
        throw std::runtime_error(log);
    }

    PeerOutput out;
    rusage children{};
    getrusage(RUSAGE_CHILDREN, &children);
    out.process_peak_rss_bytes = static_cast<long long>(children.ru_maxrss) * 1024;
    out.runtime = "wasm";
    out.triangles_seen = input.triangle_count();

    std::ifstream result(out_path, std::ios::binary);
    double timing[3];
    uint32_t counts[2];
    if (!result.read(reinterpret_cast<char*>(timing), sizeof timing) ||
        !result.read(reinterpret_cast<char*>(counts), sizeof counts))
        throw std::runtime_error(out_path.string() + ": no result header");
    out.call_seconds = timing[0];
    out.call_cpu_seconds = timing[1];
    const std::vector<uint32_t> triangles = read_array<uint32_t>(result, counts[0], out_path);
    if (!update) {
        out.surface = subset_of(input, triangles);
        return out;
    }
    if (counts[1] != n) throw std::runtime_error(out_path.string() + ": vertex count changed");
    // simplifyWithUpdate moved the vertices its collapses kept: their positions and data are the
    // output's, the data scaled back to the field's values.
    Surface moved = input;
    moved.positions = read_array<float>(result, 3 * n, out_path);
    const std::vector<float> updated = read_array<float>(result, n * attributes, out_path);
    for (size_t v = 0, at = 0; v < n; ++v)
        for (const Scaled& s : scaled) {
            Field& f = moved.fields[s.field];
            for (int c = 0; c < f.components; ++c, ++at)
                if (updated[at] != values[at]) // a value left in place keeps its exact bits
                    f.values[v * f.components + c] = float(updated[at] * s.range + s.minimum[c]);
        }
    out.surface = subset_of(moved, triangles);
    return out;
}

} // namespace ddsimp::report
