#include "surface_store.h"

#include "surface_file.h"

#include "ddsimp/protocol/content_hash.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace ddsimp::server {
namespace fs = std::filesystem;

namespace {

constexpr const char* kExtension = ".ddsurf";
constexpr const char* kScopesExtension = ".scopes";

// The scopes file: one line per scope, "SCOPE LABEL" with the public scope as "-" and the label
// in hex (labels are any bytes a client chose), and one line "+ NAME" per token that uploaded the
// surface, the name in hex.
struct Scopes {
    std::map<std::string, std::string> labels;
    std::set<std::string> tokens;
};

std::string hex(const std::string& bytes) {
    static const char* digits = "0123456789abcdef";
    std::string out;
    for (unsigned char ch : bytes) out += digits[ch >> 4], out += digits[ch & 15];
    return out;
}

std::string encode_scopes(const Scopes& s) {
    std::string out;
    for (const auto& [scope, label] : s.labels)
        out += (scope.empty() ? "-" : scope) + " " + hex(label) + "\n";
    for (const std::string& token : s.tokens) out += "+ " + hex(token) + "\n";
    return out;
}

Scopes decode_scopes(const std::string& text, const fs::path& path) {
    Scopes out;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        const size_t space = line.find(' ');
        const std::string hex = space == std::string::npos ? "" : line.substr(space + 1);
        if (space == std::string::npos || hex.size() % 2 ||
            hex.find_first_not_of("0123456789abcdef") != std::string::npos)
            throw SurfaceFileError(path.string() + ": a line that is not \"SCOPE LABEL\"");
        std::string label;
        for (size_t i = 0; i < hex.size(); i += 2)
            label += char(std::stoi(hex.substr(i, 2), nullptr, 16));
        const std::string scope = line.substr(0, space);
        if (scope == "+")
            out.tokens.insert(label);
        else
            out.labels[scope == "-" ? kPublicScope : scope] = label;
    }
    return out;
}

} // namespace

std::string session_scope(const std::string& name, const std::string& key) {
    return protocol::sha256_hex("session " + std::to_string(name.size()) + ":" + name + key);
}

StoredSurface describe_surface(const std::string& id, const std::string& name, const Surface& s) {
    StoredSurface info{id, name, s.vertex_count(), s.triangle_count(), {}};
    for (const Field& f : s.fields) {
        StoredSurface::FieldRange r{f.name, f.components, f.kind, 0, 0};
        if (!f.values.empty()) {
            const auto [lo, hi] = std::minmax_element(f.values.begin(), f.values.end());
            r.min = *lo, r.max = *hi;
        }
        info.fields.push_back(r);
    }
    return info;
}

size_t surface_bytes(const Surface& s) {
    size_t bytes = sizeof(Surface) + 4 * (s.positions.size() + s.triangles.size());
    for (const Field& f : s.fields) bytes += sizeof(Field) + f.name.size() + 4 * f.values.size();
    return bytes;
}

SurfaceStore::SurfaceStore(fs::path dir, size_t memory_bytes, size_t largest_bytes)
    : dir_(std::move(dir)), memory_limit_(memory_bytes), largest_bytes_(largest_bytes) {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec)
        throw std::runtime_error("cannot create the data directory " + dir_.string() + ": " +
                                 ec.message());
    std::vector<fs::path> files;
    for (const fs::directory_entry& e : fs::directory_iterator(dir_, ec)) files.push_back(e.path());
    if (ec)
        throw std::runtime_error("cannot read the data directory " + dir_.string() + ": " +
                                 ec.message());
    std::sort(files.begin(), files.end());
    for (const fs::path& p : files) {
        if (p.extension() == ".tmp") { // a write that never finished: never acknowledged
            spdlog::warn("removing the unfinished write {}", p.string());
            fs::remove(p, ec);
            continue;
        }
        if (p.extension() != kExtension) continue;
        try {
            const std::string id = p.stem().string();
            if (id.size() != 64 || id.find_first_not_of("0123456789abcdef") != std::string::npos)
                throw SurfaceFileError(p.string() + ": not named by a content hash");
            // The header only; the surface is read (and its hash checked) when it is needed.
            const SurfaceFileHeader header = read_surface_header(p);
            StoredSurface info{id, "", header.vertices, header.triangles, {}};
            for (const auto& f : header.fields)
                info.fields.push_back({f.name, f.components, f.kind, f.min, f.max});
            if (!header.ranges) { // an older file: its ranges need its data, once
                const Surface surface = read(id);
                info = describe_surface(id, "", surface);
            }
            fs::path scopes = p;
            scopes.replace_extension(kScopesExtension);
            Scopes seen{{{kPublicScope, header.name}}, {}}; // a file from before scopes
            if (fs::exists(scopes)) {
                std::ifstream in(scopes, std::ios::binary);
                seen = decode_scopes({std::istreambuf_iterator<char>(in), {}}, scopes);
            }
            Entry e;
            e.info = std::move(info);
            e.labels = std::move(seen.labels);
            e.tokens = std::move(seen.tokens);
            e.bytes = sizeof(Surface) + header.blob_bytes;
            entries_.emplace(id, std::move(e));
        } catch (const std::exception& e) {
            spdlog::error("skipping {}", e.what());
        }
    }
    spdlog::info("data directory {}: {} surfaces", dir_.string(), entries_.size());
}

Surface SurfaceStore::read(const std::string& id) const {
    const fs::path path = dir_ / (id + kExtension);
    SurfaceFile file = read_surface_file(path);
    const std::string hash = protocol::surface_hash(file.surface);
    if (hash != id) throw SurfaceFileError(path.string() + ": its content hash is " + hash);
    return std::move(file.surface);
}

void SurfaceStore::keep(Entry& e, const std::string& id, std::shared_ptr<const Surface> surface) {
    if (e.bytes > memory_limit_) return;
    // The least recently used surfaces that nobody else holds go first; nothing is evicted
    // unless that makes room.
    std::vector<std::string> victims;
    size_t after = resident_bytes_;
    for (auto r = recent_.rbegin(); r != recent_.rend() && after + e.bytes > memory_limit_; ++r) {
        const Entry& other = entries_.at(*r);
        if (other.surface.use_count() != 1) continue; // a job holds it
        victims.push_back(*r);
        after -= other.bytes;
    }
    if (after + e.bytes > memory_limit_) return;
    for (const std::string& v : victims) evict(entries_.at(v));
    e.surface = std::move(surface);
    resident_bytes_ += e.bytes;
    recent_.push_front(id);
    e.recent = recent_.begin();
}

void SurfaceStore::evict(Entry& e) {
    e.surface.reset();
    resident_bytes_ -= e.bytes;
    recent_.erase(e.recent);
    ++evictions_;
}

std::shared_ptr<const Surface> SurfaceStore::load(const std::string& id) {
    {
        std::lock_guard lock(mutex_);
        auto it = entries_.find(id);
        if (it == entries_.end()) return nullptr;
        Entry& e = it->second;
        if (e.surface) {
            if (!e.pinned) recent_.splice(recent_.begin(), recent_, e.recent);
            return e.surface;
        }
        if (auto held = e.in_use.lock()) { // evicted or never kept, but a job still has it
            keep(e, id, held);
            return held;
        }
        if (e.bytes > largest_bytes_ + sizeof(Surface))
            throw SurfaceFileError("surface " + id + " takes " + std::to_string(e.bytes >> 20) +
                                   " MiB, more than the largest surface the server reads "
                                   "(--max-surface-mb)");
    }
    std::shared_ptr<const Surface> loaded;
    try {
        loaded = std::make_shared<const Surface>(read(id));
    } catch (const SurfaceFileError&) {
        std::lock_guard lock(mutex_);
        if (!entries_.count(id)) return nullptr; // deleted while it was being read
        throw;
    }
    std::lock_guard lock(mutex_);
    ++loads_;
    auto it = entries_.find(id);
    if (it == entries_.end()) return loaded; // deleted meanwhile: the caller's alone
    Entry& e = it->second;
    if (e.surface) return e.surface; // another thread read it meanwhile
    if (auto held = e.in_use.lock()) {
        keep(e, id, held);
        return held;
    }
    e.bytes = surface_bytes(*loaded);
    e.in_use = loaded;
    keep(e, id, loaded);
    return loaded;
}

SurfaceStore::Residency SurfaceStore::residency() const {
    std::lock_guard lock(mutex_);
    return {recent_.size(), resident_bytes_, pinned_bytes_, memory_limit_,
            loads_,         evictions_,      removals_};
}

std::optional<StoredSurface> SurfaceStore::visible(const Entry& e,
                                                   const std::set<std::string>& scopes) {
    for (const std::string& scope : scopes)
        if (auto label = e.labels.find(scope); label != e.labels.end()) {
            StoredSurface info = e.info;
            info.name = label->second;
            return info;
        }
    return std::nullopt;
}

void SurfaceStore::write_scopes(const std::string& id,
                                const std::map<std::string, std::string>& labels,
                                const std::set<std::string>& tokens) {
    write_file_atomically(dir_ / (id + kScopesExtension), encode_scopes({labels, tokens}));
}

SurfaceStore::Added SurfaceStore::insert(const std::string& id, const std::string& name,
                                         Surface surface, const std::string& scope,
                                         const std::string& token, bool write) {
    const std::set<std::string> seen_by{kPublicScope, scope};
    // Disk writes one at a time: the scopes written are always the union of all added so far.
    std::unique_lock files(files_mutex_, std::defer_lock);
    if (write) files.lock();
    std::map<std::string, std::string> labels;
    std::set<std::string> tokens;
    bool known = false;
    {
        std::lock_guard lock(mutex_);
        if (auto it = entries_.find(id); it != entries_.end()) {
            // Already there: it costs nothing more, so nobody is charged for it again.
            if (auto info = visible(it->second, seen_by)) return {*info, true};
            known = true;
            labels = it->second.labels;
            tokens = it->second.tokens;
        }
    }
    labels.emplace(scope, name);
    if (!token.empty()) tokens.insert(token);
    if (write) { // (in-memory surfaces are public: never here)
        // Scopes first: a crash between the two writes leaves scopes without a surface (ignored),
        // never a surface without its scopes (which would make it public).
        write_scopes(id, labels, tokens);
        if (!known)
            write_file_atomically(dir_ / (id + kExtension), encode_surface_file(name, surface));
    }
    StoredSurface info = describe_surface(id, "", surface);
    const size_t bytes = surface_bytes(surface);
    auto held = std::make_shared<const Surface>(std::move(surface));
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end()) {
        it = entries_.emplace(id, Entry{}).first;
        Entry& e = it->second;
        e.info = std::move(info);
        e.bytes = bytes;
        e.in_use = held;
        if (write) { // just uploaded: likely asked for soon
            keep(e, id, std::move(held));
        } else {
            e.pinned = true;
            e.surface = std::move(held);
            pinned_bytes_ += bytes;
        }
    }
    it->second.labels.emplace(scope, name);
    if (!token.empty()) it->second.tokens.insert(token);
    return {*visible(it->second, {scope}), false};
}

SurfaceStore::Added SurfaceStore::add(const std::string& name, Surface surface,
                                      const std::string& scope, const std::string& token) {
    const std::string id = protocol::surface_hash(surface);
    return insert(id, name, std::move(surface), scope, token, true);
}

SurfaceStore::Added SurfaceStore::add_in_memory(const std::string& name, Surface surface) {
    const std::string id = protocol::surface_hash(surface);
    return insert(id, name, std::move(surface), kPublicScope, "", false);
}

bool SurfaceStore::share(const std::string& id, const std::set<std::string>& scopes,
                         const std::string& scope) {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end()) return false;
    const std::optional<StoredSurface> info = visible(it->second, scopes);
    if (!info) return false;
    if (!visible(it->second, {kPublicScope, scope})) it->second.labels.emplace(scope, info->name);
    return true;
}

void SurfaceStore::persist_scopes(const std::string& id) {
    std::lock_guard files(files_mutex_);
    std::map<std::string, std::string> labels;
    std::set<std::string> tokens;
    {
        std::lock_guard lock(mutex_);
        auto it = entries_.find(id);
        if (it == entries_.end() || it->second.labels.count(kPublicScope))
            return; // nothing to keep
        labels = it->second.labels;
        tokens = it->second.tokens;
    }
    write_scopes(id, labels, tokens);
}

SurfaceStore::Removal SurfaceStore::remove(const std::string& id,
                                           const std::set<std::string>& scopes,
                                           const std::string& token, bool one_user) {
    // The same order as insert(): a re-upload of the same bytes never interleaves with this.
    std::lock_guard files(files_mutex_);
    std::map<std::string, std::string> labels;
    std::set<std::string> tokens;
    {
        std::lock_guard lock(mutex_);
        auto it = entries_.find(id);
        if (it == entries_.end() || !visible(it->second, scopes)) return Removal::NotFound;
        Entry& e = it->second;
        if (e.pinned) return Removal::Pinned;
        if (!one_user) {
            if (!e.tokens.count(token)) return Removal::NotOwner;
            if (e.tokens.size() > 1) {
                e.tokens.erase(token);
                labels = e.labels;
                tokens = e.tokens;
            }
        }
        if (tokens.empty()) { // out of the index first: no new job finds it
            if (e.surface) resident_bytes_ -= e.bytes, recent_.erase(e.recent);
            entries_.erase(it);
            ++removals_;
        }
    }
    if (!tokens.empty()) {
        write_scopes(id, labels, tokens);
        return Removal::Released;
    }
    // The surface before its scopes: a crash between the two leaves scopes without a surface,
    // which the next start ignores.
    std::error_code ec;
    for (const char* extension : {kExtension, kScopesExtension}) {
        const fs::path path = dir_ / (id + extension);
        if (!fs::remove(path, ec) && ec)
            throw SurfaceFileError("cannot remove " + path.string() + ": " + ec.message());
    }
    return Removal::Removed;
}

bool SurfaceStore::would_charge(const std::string& id, const std::string& scope) const {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    return it == entries_.end() || !visible(it->second, {kPublicScope, scope});
}

std::optional<StoredSurface> SurfaceStore::find(const std::string& id,
                                                const std::set<std::string>& scopes) const {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end()) return std::nullopt;
    return visible(it->second, scopes);
}

std::vector<StoredSurface> SurfaceStore::list(const std::set<std::string>& scopes) const {
    std::vector<StoredSurface> out;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [id, e] : entries_)
            if (auto info = visible(e, scopes)) out.push_back(std::move(*info));
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.name < b.name; });
    return out;
}

SurfaceStore::Usage SurfaceStore::usage_of_token(const std::string& token) const {
    std::lock_guard lock(mutex_);
    Usage u;
    for (const auto& [id, e] : entries_)
        if (e.tokens.count(token)) ++u.surfaces, u.bytes += e.bytes;
    return u;
}

SurfaceStore::Usage SurfaceStore::usage_of_scope(const std::string& scope) const {
    std::lock_guard lock(mutex_);
    Usage u;
    for (const auto& [id, e] : entries_)
        if (e.labels.count(scope)) ++u.surfaces, u.bytes += e.bytes;
    return u;
}

size_t SurfaceStore::size() const {
    std::lock_guard lock(mutex_);
    return entries_.size();
}

} // namespace ddsimp::server
