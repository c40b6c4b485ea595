#include "server_watch.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>

namespace ddsimp::load {

size_t status_bytes(int pid, const std::string& key) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind(key + ":", 0) == 0)
            return size_t(std::stoull(line.substr(key.size() + 1))) << 10;
    return 0;
}

bool reset_peak(int pid) {
    std::ofstream out("/proc/" + std::to_string(pid) + "/clear_refs");
    out << "5\n";
    out.flush();
    return bool(out);
}

RssSampler::RssSampler(int pid, double period_seconds) : pid_(pid) {
    thread_ = std::thread([this, period_seconds] {
        while (!stop_) {
            const size_t now = status_bytes(pid_, "VmRSS");
            if (now > peak_) peak_ = now;
            std::this_thread::sleep_for(std::chrono::duration<double>(period_seconds));
        }
    });
}

RssSampler::~RssSampler() {
    stop_ = true;
    thread_.join();
}

MemoryFlags memory_flags_of(int pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline", std::ios::binary);
    std::vector<std::string> args;
    for (std::string arg; std::getline(in, arg, '\0');) args.push_back(arg);
    MemoryFlags f;
    const std::map<std::string, double*> numbers = {
        {"--surfaces-mb", &f.surfaces_mb},         {"--cache-mb", &f.cache_mb},
        {"--max-queue-mb", &f.max_queue_mb},       {"--max-upload-mb", &f.max_upload_mb},
        {"--max-frame-bytes", &f.max_frame_bytes}, {"--max-remembered-kb", &f.max_remembered_kb}};
    for (size_t i = 0; i + 1 < args.size(); ++i) {
        std::string name = args[i], value = args[i + 1];
        if (const size_t eq = name.find('='); eq != std::string::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
        }
        if (auto it = numbers.find(name); it != numbers.end()) *it->second = std::stod(value);
        if (name == "--max-clients") f.max_clients = std::stoi(value);
        if (name == "--threads") f.threads = std::stoi(value);
    }
    return f;
}

namespace {

std::string escaped(const std::string& line) {
    std::string out;
    for (unsigned char ch : line.substr(0, 160)) {
        if (ch >= 0x20 && ch < 0x7f && ch != '\\') {
            out += char(ch);
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", ch);
            out += hex;
        }
    }
    return out;
}

} // namespace

LogScan scan_log(const std::string& path, const std::string& forged_marker) {
    // spdlog's pattern "%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v" (server/src/logging.cpp).
    static const std::regex text_line(
        R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3} (trace|debug|info|warning|error|critical) ([\x20-\x7e]*))");
    LogScan scan;
    std::ifstream in(path, std::ios::binary);
    for (std::string line; std::getline(in, line);) {
        ++scan.lines;
        std::string message;
        bool parsed = false;
        if (!line.empty() && line[0] == '{') {
            const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
            parsed = j.is_object() && j.size() == 3 && j.contains("time") &&
                     j["time"].is_string() && j.contains("level") && j["level"].is_string() &&
                     j.contains("message") && j["message"].is_string();
            if (parsed) message = j["message"].get<std::string>();
            for (unsigned char ch : line) parsed = parsed && ch >= 0x20 && ch < 0x7f;
        } else {
            std::smatch m;
            parsed = std::regex_match(line, m, text_line);
            if (parsed) message = m[2];
        }
        const bool forged = message.rfind(forged_marker, 0) == 0;
        if (!parsed) ++scan.unparsed;
        if (forged) ++scan.forged;
        if ((!parsed || forged) && scan.examples.size() < 5) scan.examples.push_back(escaped(line));
    }
    return scan;
}

} // namespace ddsimp::load
