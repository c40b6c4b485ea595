// ddsimp_bench_memory: peak memory of one ddsimp simplification per input triangle.
//
//   ddsimp_bench_memory IN --strategy edge|vertex [--keep F] [--alpha A]
//
// Run it once per strategy, each in a fresh process. It loads IN, hands the loader's free memory
// back to the kernel (malloc_trim), records the resident set size (VmRSS), resets the kernel's
// peak-RSS mark (writes 5 to /proc/self/clear_refs), simplifies, and reads the peak (VmHWM). The
// figure is (peak RSS - RSS before simplify) / input triangles: what the machine really pays for
// the call, allocator overhead and fragmentation included, the caller's input surface excluded,
// the result surface included.
//
// As a cross-check it also counts the bytes the program asks for through operator new (the
// replacement below): the peak of live heap bytes during the call over the live bytes before it.
// That figure ignores allocator overhead and pages never touched; the two should be close.
//
// Prints one JSON object on stdout. Exit status: 0 on success, 1 if simplify throws, 2 for bad
// arguments or an unreadable file.
#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target

#include <ddsimp/ddsimp.h>

#include <malloc.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <new>
#include <string>

// ---------------------------------------------------------------------------------------------
// Heap accounting: every operator new / delete of the program goes through these.
// ---------------------------------------------------------------------------------------------
namespace {
std::atomic<long long> g_heap_live{0};
std::atomic<long long> g_heap_peak{0};

void* counted_alloc(std::size_t size, std::size_t alignment) {
    if (size == 0) size = 1;
    void* p = nullptr;
    if (alignment <= alignof(std::max_align_t)) {
        p = std::malloc(size);
    } else if (posix_memalign(&p, alignment, size) != 0) {
        p = nullptr;
    }
    if (!p) return nullptr;
    const long long live = g_heap_live.fetch_add(static_cast<long long>(malloc_usable_size(p)),
                                                 std::memory_order_relaxed) +
                           static_cast<long long>(malloc_usable_size(p));
    long long peak = g_heap_peak.load(std::memory_order_relaxed);
    while (live > peak &&
           !g_heap_peak.compare_exchange_weak(peak, live, std::memory_order_relaxed)) {
    }
    return p;
}

void counted_free(void* p) noexcept {
    if (!p) return;
    g_heap_live.fetch_sub(static_cast<long long>(malloc_usable_size(p)), std::memory_order_relaxed);
    std::free(p);
}

void* counted_new(std::size_t size, std::size_t alignment) {
    void* p = counted_alloc(size, alignment);
    if (!p) throw std::bad_alloc();
    return p;
}
} // namespace

void* operator new(std::size_t n) {
    return counted_new(n, alignof(std::max_align_t));
}
void* operator new[](std::size_t n) {
    return counted_new(n, alignof(std::max_align_t));
}
void* operator new(std::size_t n, std::align_val_t a) {
    return counted_new(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
    return counted_new(n, static_cast<std::size_t>(a));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    return counted_alloc(n, alignof(std::max_align_t));
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
    return counted_alloc(n, alignof(std::max_align_t));
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
    return counted_alloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
    return counted_alloc(n, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept {
    counted_free(p);
}
void operator delete[](void* p) noexcept {
    counted_free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    counted_free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    counted_free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
    counted_free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
    counted_free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
    counted_free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
    counted_free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    counted_free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    counted_free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
    counted_free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
    counted_free(p);
}

// ---------------------------------------------------------------------------------------------
// RSS from /proc/self/status
// ---------------------------------------------------------------------------------------------
namespace {

// The value of a "Key:   1234 kB" line of /proc/self/status, in bytes; -1 if absent.
long long status_bytes(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    const size_t len = std::strlen(key);
    while (std::getline(in, line)) {
        if (line.compare(0, len, key) == 0 && line.size() > len && line[len] == ':') {
            return std::atoll(line.c_str() + len + 1) * 1024;
        }
    }
    return -1;
}

// Resets VmHWM to the current RSS (Linux >= 4.0). False if the kernel refused.
bool reset_peak_rss() {
    std::ofstream out("/proc/self/clear_refs");
    out << "5" << std::flush;
    return static_cast<bool>(out);
}

// `text` as a JSON string literal.
std::string json_string(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
            out += buf;
        } else {
            out += c;
        }
    }
    return out + '"';
}

[[noreturn]] void usage(const char* message) {
    std::fprintf(stderr,
                 "ddsimp_bench_memory: %s\n"
                 "usage: ddsimp_bench_memory IN --strategy edge|vertex [--keep F] [--alpha A]\n",
                 message);
    std::exit(2);
}

} // namespace

int main(int argc, char** argv) {
    std::string path;
    std::string strategy_name;
    ddsimp::Options options;
    options.alpha = 0.5;
    options.keep_fraction = 0.1;
    options.placement = ddsimp::Placement::Midpoint;
    options.threads = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(("missing value after " + arg).c_str());
            return argv[++i];
        };
        if (arg == "--strategy") {
            strategy_name = value();
        } else if (arg == "--keep") {
            options.keep_fraction = std::atof(value().c_str());
        } else if (arg == "--alpha") {
            options.alpha = std::atof(value().c_str());
        } else if (!arg.empty() && arg[0] != '-' && path.empty()) {
            path = arg;
        } else {
            usage(("unknown argument " + arg).c_str());
        }
    }
    if (path.empty()) usage("no input surface");
    if (strategy_name == "edge") {
        options.strategy = ddsimp::Strategy::EdgeCollapse;
    } else if (strategy_name == "vertex") {
        options.strategy = ddsimp::Strategy::VertexRemoval;
    } else {
        usage("--strategy must be edge or vertex");
    }

    ddsimp::Surface surface;
    try {
        surface = ddsimp::io::read_surface(path);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddsimp_bench_memory: cannot read %s: %s\n", path.c_str(), e.what());
        return 2;
    }
    const size_t triangles = surface.triangle_count();
    if (triangles == 0) {
        std::fprintf(stderr, "ddsimp_bench_memory: %s has no triangles\n", path.c_str());
        return 2;
    }

    // The baseline: the loaded surface and nothing the loader freed.
    malloc_trim(0);
    const long long rss_before = status_bytes("VmRSS");
    const bool peak_reset = reset_peak_rss();
    const long long hwm_before = status_bytes("VmHWM");
    const long long heap_before = g_heap_live.load();
    g_heap_peak.store(heap_before);

    size_t triangles_out = 0;
    bool target_reached = false;
    const auto start = std::chrono::steady_clock::now();
    try {
        ddsimp::Result result = ddsimp::simplify(surface, options);
        triangles_out = result.triangles_out;
        target_reached = result.target_reached;
        // The result is alive here, so the peak below includes it.
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddsimp_bench_memory: simplify failed: %s\n", e.what());
        return 1;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long long hwm_after = status_bytes("VmHWM");
    const long long heap_peak = g_heap_peak.load() - heap_before;
    const long long rss_peak = hwm_after - rss_before;

    // If the peak mark could not be reset, an earlier, higher peak (the loader's) can hide the
    // call's: say so instead of printing a number that may be too low.
    const bool rss_valid = peak_reset || hwm_before <= rss_before;
    std::printf("{\"surface\": %s, \"strategy\": \"%s\", \"triangles_in\": %zu, "
                "\"triangles_out\": %zu, \"target_reached\": %s, \"seconds\": %.3f, "
                "\"rss_before_bytes\": %lld, \"peak_rss_bytes\": %lld, "
                "\"peak_rss_valid\": %s, \"bytes_per_triangle\": %.1f, "
                "\"heap_peak_bytes\": %lld, \"heap_bytes_per_triangle\": %.1f}\n",
                json_string(path).c_str(), strategy_name.c_str(), triangles, triangles_out,
                target_reached ? "true" : "false", seconds, rss_before, hwm_after,
                rss_valid ? "true" : "false",
                static_cast<double>(rss_peak) / static_cast<double>(triangles), heap_peak,
                static_cast<double>(heap_peak) / static_cast<double>(triangles));
    return 0;
}
