// What ddsimp-load's hostile mode measures of the server process on the same machine: its
// resident memory (sampled, and the kernel's peak), the limits it was started with, and whether
// every line of its log is one the
// logger wrote.
#pragma once

#include <atomic>
#include <cstddef>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace ddsimp::load {

// A field of /proc/PID/status in bytes ("VmRSS", "VmHWM"); 0 if absent.
size_t status_bytes(int pid, const std::string& key);
// Resets the process's VmHWM to its present VmRSS (/proc/PID/clear_refs); false if not allowed.
bool reset_peak(int pid);

// Samples VmRSS every `period` on a thread of its own.
class RssSampler {
public:
    RssSampler(int pid, double period_seconds);
    ~RssSampler();
    size_t peak() const { return peak_; }

private:
    int pid_;
    std::atomic<bool> stop_{false};
    std::atomic<size_t> peak_{0};
    std::thread thread_;
};

// The server's flags that bound its memory, read from its command line (/proc/PID/cmdline),
// the documented defaults for those not given.
struct MemoryFlags {
    double surfaces_mb = 512, cache_mb = 512, max_queue_mb = 256, max_upload_mb = 1024;
    double max_frame_bytes = 4 << 20, max_remembered_kb = 16384;
    int max_clients = 256, threads = 2;
};
MemoryFlags memory_flags_of(int pid);

// Lines of the server's log that the logger did not write as one event: lines that are not
// "DATE TIME LEVEL printable-ASCII" (text) or one JSON object with time, level and message
// (--log-format json), and lines whose message begins with `forged_marker`.
struct LogScan {
    long lines = 0;
    long unparsed = 0;
    long forged = 0;
    std::vector<std::string> examples; // the first few bad lines, escaped
};
LogScan scan_log(const std::string& path, const std::string& forged_marker);

} // namespace ddsimp::load
