#include "hostile_mode.h"

#include "hostile_attacks.h"
#include "server_watch.h"

#include "ddsimp/client.h"
#include "ddsimp/io/surface_io.h" // io/, from the ddsimp_io target
#include "ddsimp/protocol/mesh_codec.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <mutex>

namespace ddsimp::load {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
constexpr double kMiB = 1 << 20;

enum Phase { kBefore, kDuring, kAfter, kPhases };
const char* phase_name(int p) {
    return p == kBefore ? "before" : p == kDuring ? "during" : "after";
}

ConnectOptions connect_options(const HostileSettings& s, const std::string& name) {
    ConnectOptions o;
    o.host = s.host;
    o.port = s.port;
    o.token = s.token;
    o.tls = s.tls;
    o.tls_insecure = s.tls;
    o.client_name = name;
    o.timeout = std::chrono::minutes(5);
    return o;
}

// Clients that keep asking for a cached level of the main surface, each on its own connection
// made before the attack, and record how long each answer took, by phase.
class NormalClients {
public:
    NormalClients(const HostileSettings& s, const std::string& surface) {
        for (int i = 0; i < s.normal_clients; ++i) {
            auto client = std::make_unique<Client>();
            client->connect(connect_options(s, "ddsimp-load normal " + std::to_string(i)));
            clients_.push_back(std::move(client));
        }
        for (int i = 0; i < s.normal_clients; ++i)
            threads_.emplace_back([this, &s, surface, i] { run(s, surface, i); });
    }
    ~NormalClients() { stop(); }
    void set_phase(Phase p) { phase_ = p; }
    void stop() {
        stop_ = true;
        for (auto& t : threads_) t.join();
        threads_.clear();
    }
    std::vector<double> seconds(Phase p) const {
        std::lock_guard lock(mutex_);
        return seconds_[p];
    }
    long failures(Phase p) const {
        std::lock_guard lock(mutex_);
        return failures_[p];
    }
    std::vector<std::string> errors() const {
        std::lock_guard lock(mutex_);
        return errors_;
    }

private:
    void run(const HostileSettings& s, const std::string& surface, int index) {
        Client& client = *clients_[size_t(index)];
        for (uint64_t n = 0; !stop_; ++n) {
            LevelRequest r;
            r.surface = surface;
            r.alpha = s.alpha;
            r.keep = {s.keeps[(n + size_t(index)) % s.keeps.size()]};
            const Phase phase = phase_;
            const auto start = Clock::now();
            try {
                const std::vector<Level> levels = client.request_levels(r);
                const double t = std::chrono::duration<double>(Clock::now() - start).count();
                std::lock_guard lock(mutex_);
                if (levels.size() == 1 && levels[0].cached) {
                    seconds_[phase].push_back(t);
                } else {
                    ++failures_[phase];
                    errors_.push_back("a level that was not cached");
                }
            } catch (const std::exception& e) {
                std::lock_guard lock(mutex_);
                ++failures_[phase];
                if (errors_.size() < 20)
                    errors_.push_back(std::string(phase_name(phase)) + ": " + e.what());
                if (!client.connected()) return;
            }
            std::this_thread::sleep_for(100ms);
        }
    }

    std::vector<std::unique_ptr<Client>> clients_;
    std::vector<std::thread> threads_;
    std::atomic<bool> stop_{false};
    std::atomic<Phase> phase_{kBefore};
    mutable std::mutex mutex_;
    std::vector<double> seconds_[kPhases];
    long failures_[kPhases] = {};
    std::vector<std::string> errors_;
};

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

// The median of VmRSS sampled over `seconds`: the server's memory at rest.
size_t resting_rss(int pid, double seconds) {
    std::vector<double> samples;
    for (const auto until = Clock::now() + std::chrono::duration<double>(seconds);
         Clock::now() < until; std::this_thread::sleep_for(100ms))
        samples.push_back(double(status_bytes(pid, "VmRSS")));
    return size_t(quantile(samples, 0.5));
}

// The parts of the server's own accounting the attack can raise (their peaks are kept).
const std::vector<std::string> kGauges = {"ddsimp_sockets",           "ddsimp_connections",
                                          "ddsimp_surface_bytes",     "ddsimp_queue_bytes",
                                          "ddsimp_upload_bytes",      "ddsimp_cache_bytes",
                                          "ddsimp_request_job_bytes", "ddsimp_request_jobs",
                                          "ddsimp_remembered_bytes",  "ddsimp_remembered_results"};
const std::vector<std::string> kCounters = {
    "ddsimp_connections_refused_total",  "ddsimp_accept_errors_total",
    "ddsimp_request_errors_total",       "ddsimp_computations_total",
    "ddsimp_reductions_cancelled_total", "ddsimp_bad_frames_total",
    "ddsimp_connections_dropped_total",  "ddsimp_quota_refusals_total"};

} // namespace

int run_hostile(const HostileSettings& s) {
    if (s.server_pid <= 0 || s.http_port == 0 || s.surface.empty())
        throw std::invalid_argument("--hostile needs --server-pid, --http-port and --surface");
    nlohmann::json report;
    use_tls(s.tls);
    // OpenSSL writes with write(): a connection the server closed would raise SIGPIPE.
    std::signal(SIGPIPE, SIG_IGN);
    report["tls"] = s.tls;
    const int pid = s.server_pid;
    const size_t at_rest = status_bytes(pid, "VmRSS");

    // The big surface, uploaded and one level of it cached.
    const Surface big = io::read_surface(s.surface);
    std::string surface;
    {
        Client setup;
        setup.connect(connect_options(s, "ddsimp-load hostile setup"));
        surface = setup.upload(big, "hostile-main").surface;
        LevelRequest r;
        r.surface = surface;
        r.alpha = s.alpha;
        r.keep = s.keeps;
        const auto start = Clock::now();
        setup.request_levels(r);
        report["warm_up_seconds"] = std::chrono::duration<double>(Clock::now() - start).count();
    }
    const auto progress = [](const std::string& what) {
        std::cerr << "ddsimp-load: " << what << std::endl;
    };
    progress("surface uploaded, one level cached");
    HttpKeepAlive http(s.host, s.http_port);
    const auto metrics = [&] { return parse_metrics(http.get("/metrics").value_or("")); };
    // The server's own speculation after an upload (other alphas of the surface) ends first.
    for (std::map<std::string, double> m = metrics();
         m["ddsimp_speculations_pending"] > 0 || m["ddsimp_reductions_running"] > 0; m = metrics())
        std::this_thread::sleep_for(500ms);

    NormalClients normal(s, surface);
    std::this_thread::sleep_for(5s);
    const size_t idle = resting_rss(pid, 3);
    const std::map<std::string, double> before = metrics();
    const auto value = [](const std::map<std::string, double>& m, const std::string& name) {
        return m.count(name) ? m.at(name) : 0.0;
    };

    Target target;
    target.host = s.host;
    target.port = s.port;
    target.http_port = s.http_port;
    target.token = s.token;
    target.big_surface = surface;
    const MemoryFlags flags = memory_flags_of(pid);
    target.max_frame_bytes = size_t(flags.max_frame_bytes);
    target.max_clients =
        int(before.count("ddsimp_sockets_limit") ? before.at("ddsimp_sockets_limit")
                                                 : flags.max_clients);
    const bool peak_reset = reset_peak(pid);

    std::map<std::string, double> peaks;
    std::map<std::string, long> attack_counts;
    size_t sampled_peak = 0;
    {
        RssSampler sampler(pid, 0.05);
        normal.set_phase(kDuring);
        Attacks attacks(target);
        attacks.start();
        progress("every attack started");
        for (const auto until = Clock::now() + std::chrono::duration<double>(s.attack_seconds);
             Clock::now() < until; std::this_thread::sleep_for(1s)) {
            for (const auto& [name, value] : metrics())
                if (std::find(kGauges.begin(), kGauges.end(), name) != kGauges.end())
                    peaks[name] = std::max(peaks[name], value);
        }
        progress("stopping the attacks");
        attacks.stop();
        progress("attacks stopped");
        attack_counts = attacks.counts();
        normal.set_phase(kAfter);
        sampled_peak = sampler.peak();
    }
    const size_t peak = std::max(peak_reset ? status_bytes(pid, "VmHWM") : 0, sampled_peak);

    // After: the attackers' jobs and uploads end, then the memory at rest again.
    const auto settle_start = Clock::now();
    for (std::map<std::string, double> m = metrics();
         (m["ddsimp_request_jobs"] > 0 || m["ddsimp_reductions_running"] > 0 ||
          m["ddsimp_upload_bytes"] > 0) &&
         Clock::now() - settle_start < 600s;
         m = metrics())
        std::this_thread::sleep_for(500ms);
    progress("the server's jobs and uploads have ended");
    report["settle_seconds"] = std::chrono::duration<double>(Clock::now() - settle_start).count();
    std::this_thread::sleep_for(5s);
    const size_t after = resting_rss(pid, 3);
    normal.stop();
    const std::map<std::string, double> end = metrics();

    // A client that connects after the attack is served.
    bool new_client_served = false;
    try {
        Client late;
        late.connect(connect_options(s, "ddsimp-load after the attack"));
        LevelRequest r;
        r.surface = surface;
        r.alpha = s.alpha;
        r.keep = {s.keeps[0]};
        new_client_served = late.request_levels(r).size() == 1;
    } catch (const std::exception&) {
    }

    // The server's own total for the flags it runs with, beyond its memory at rest.
    const double stated = value(before, "ddsimp_memory_bound_bytes");
    const double documented = double(at_rest) + stated;
    const LogScan log = s.server_log.empty() ? LogScan{} : scan_log(s.server_log, kForgedMarker);

    // The report.
    for (int p = kBefore; p < kPhases; ++p) {
        const std::vector<double> t = normal.seconds(Phase(p));
        report["normal"][phase_name(p)] = {{"answers", t.size()},
                                           {"failures", normal.failures(Phase(p))},
                                           {"median_ms", 1e3 * quantile(t, 0.5)},
                                           {"p99_ms", 1e3 * quantile(t, 0.99)},
                                           {"max_ms", 1e3 * quantile(t, 1.0)}};
    }
    report["normal_errors"] = normal.errors();
    report["attack_seconds"] = s.attack_seconds;
    report["attacks"] = attack_counts;
    report["memory_mib"] = {
        {"at_rest", at_rest / kMiB},     {"idle", idle / kMiB},
        {"peak", peak / kMiB},           {"peak_sampled", sampled_peak / kMiB},
        {"peak_from_vmhwm", peak_reset}, {"after", after / kMiB},
        {"stated_bound", stated / kMiB}, {"documented_total", documented / kMiB}};
    report["metrics_peaks_during"] = peaks;
    for (const std::string& name : kCounters)
        report["metrics_counted_during_and_after"][name] =
            end.count(name) && before.count(name) ? end.at(name) - before.at(name) : -1.0;
    report["metrics_after"] = {
        {"ddsimp_cache_bytes", end.count("ddsimp_cache_bytes") ? end.at("ddsimp_cache_bytes") : -1},
        {"ddsimp_surface_bytes",
         end.count("ddsimp_surface_bytes") ? end.at("ddsimp_surface_bytes") : -1}};
    report["log"] = {{"lines", log.lines},
                     {"unparsed", log.unparsed},
                     {"forged", log.forged},
                     {"examples", log.examples}};
    report["new_client_served_after"] = new_client_served;

    const auto during = report["normal"]["during"];
    const bool latency_ok = during["answers"].get<size_t>() > 0 && during["failures"] == 0 &&
                            during["max_ms"].get<double>() <= 1000;
    const bool memory_ok = stated > 0 && double(peak) <= 1.1 * documented;
    const bool log_ok =
        !s.server_log.empty() && log.lines > 0 && log.unparsed == 0 && log.forged == 0;
    // The results the attackers asked for stay cached within --cache-mb, as any result does:
    // what the cache gained is counted apart from the rest of the memory.
    const double cache_gain =
        std::max(0.0, value(end, "ddsimp_cache_bytes") - value(before, "ddsimp_cache_bytes"));
    report["memory_mib"]["cache_gain_after"] = cache_gain / kMiB;
    report["memory_mib"]["after_less_cache_gain"] = (double(after) - cache_gain) / kMiB;
    const bool recovered = double(after) - cache_gain <= 1.1 * double(idle);
    report["goals"] = {{"cached_level_within_1s", latency_ok},
                       {"peak_within_documented_plus_10pct", memory_ok},
                       {"no_forged_log_line", log_ok},
                       {"back_within_10pct_of_idle", recovered}};

    if (s.json) {
        std::cout << report.dump() << "\n";
    } else {
        std::printf(
            "hostile run: %.0f s of every attack at once, %d normal clients, warm-up %.1f s\n",
            s.attack_seconds, s.normal_clients, report["warm_up_seconds"].get<double>());
        std::printf("%-8s %8s %9s %10s %10s %10s  (cached level, ms)\n", "phase", "answers",
                    "failures", "median", "p99", "max");
        for (int p = kBefore; p < kPhases; ++p) {
            const auto& n = report["normal"][phase_name(p)];
            std::printf("%-8s %8zu %9ld %10.1f %10.1f %10.1f\n", phase_name(p),
                        n["answers"].get<size_t>(), n["failures"].get<long>(),
                        n["median_ms"].get<double>(), n["p99_ms"].get<double>(),
                        n["max_ms"].get<double>());
        }
        std::printf("server memory (MiB): at rest %.0f, idle %.0f, peak %.0f (%s), after %.0f "
                    "(%.0f of it results the attack added to the cache); total %.0f (at rest + "
                    "the server's ddsimp_memory_bound_bytes %.0f)\n",
                    at_rest / kMiB, idle / kMiB, peak / kMiB,
                    peak_reset ? "VmHWM since the attack began" : "VmRSS sampled", after / kMiB,
                    cache_gain / kMiB, documented / kMiB, stated / kMiB);
        std::printf("server's accounting, peaks during the attack:\n");
        for (const auto& [name, value] : peaks)
            std::printf("  %-28s %14.0f\n", name.c_str(), value);
        std::printf("counted from before the attack to after it:\n");
        for (const auto& [name, value] : report["metrics_counted_during_and_after"].items())
            std::printf("  %-36s %10.0f\n", name.c_str(), value.get<double>());
        std::printf("attacks:\n");
        for (const auto& [name, n] : attack_counts) std::printf("  %-44s %9ld\n", name.c_str(), n);
        std::printf("log: %ld lines, %ld not the logger's format, %ld forged\n", log.lines,
                    log.unparsed, log.forged);
        for (const std::string& e : log.examples) std::printf("  bad line: %s\n", e.c_str());
        for (const std::string& e : normal.errors())
            std::printf("  normal client: %s\n", e.c_str());
        std::printf("a client connecting after the attack is served: %s\n",
                    new_client_served ? "yes" : "no");
        std::printf("goals: cached level within 1 s: %s; peak within documented + 10%%: %s; "
                    "no forged log line: %s; back within 10%% of idle: %s\n",
                    latency_ok ? "met" : "MISSED", memory_ok ? "met" : "MISSED",
                    log_ok ? "met" : "MISSED", recovered ? "met" : "MISSED");
    }
    return latency_ok && memory_ok && log_ok && recovered && new_client_served ? 0 : 1;
}

} // namespace ddsimp::load
