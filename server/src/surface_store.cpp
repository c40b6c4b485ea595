#include "surface_store.h"

#include "surface_file.h"

#include "ddsimp/protocol/content_hash.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <limits>

namespace ddsimp::server {
namespace fs = std::filesystem;

namespace {
constexpr const char* kExtension = ".ddsurf";
}

StoredSurface describe_surface(const std::string& id, const std::string& name, const Surface& s) {
    StoredSurface info{id, name, s.vertex_count(), s.triangle_count(), {}};
    for (const Field& f : s.fields) {
        StoredSurface::FieldRange r{f.name, f.components, 0, 0};
        if (!f.values.empty()) {
            const auto [lo, hi] = std::minmax_element(f.values.begin(), f.values.end());
            r.min = *lo, r.max = *hi;
        }
        info.fields.push_back(r);
    }
    return info;
}

SurfaceStore::SurfaceStore(fs::path dir) : dir_(std::move(dir)) {
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
            SurfaceFile file = read_surface_file(p);
            const std::string id = protocol::surface_hash(file.surface);
            if (id != p.stem().string()) {
                spdlog::error("skipping {}: its content hash is {}", p.string(), id);
                continue;
            }
            insert(id, file.name, std::move(file.surface), false);
        } catch (const std::exception& e) {
            spdlog::error("skipping {}", e.what());
        }
    }
    spdlog::info("data directory {}: {} surfaces", dir_.string(), entries_.size());
}

SurfaceStore::Added SurfaceStore::insert(const std::string& id, const std::string& name,
                                         Surface surface, bool write) {
    {
        std::lock_guard lock(mutex_);
        if (auto it = entries_.find(id); it != entries_.end()) return {it->second.info, true};
    }
    // Written outside the lock; two uploads of the same surface write the same bytes.
    if (write) write_file_atomically(dir_ / (id + kExtension), encode_surface_file(name, surface));
    StoredSurface info = describe_surface(id, name, surface);
    std::lock_guard lock(mutex_);
    auto [it, inserted] =
        entries_.try_emplace(id, Entry{info, std::make_shared<const Surface>(std::move(surface))});
    return {it->second.info, !inserted};
}

SurfaceStore::Added SurfaceStore::add(const std::string& name, Surface surface) {
    const std::string id = protocol::surface_hash(surface);
    return insert(id, name, std::move(surface), true);
}

SurfaceStore::Added SurfaceStore::add_in_memory(const std::string& name, Surface surface) {
    const std::string id = protocol::surface_hash(surface);
    return insert(id, name, std::move(surface), false);
}

std::optional<StoredSurface> SurfaceStore::find(const std::string& id) const {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end()) return std::nullopt;
    return it->second.info;
}

std::shared_ptr<const Surface> SurfaceStore::load(const std::string& id) const {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    return it == entries_.end() ? nullptr : it->second.surface;
}

std::vector<StoredSurface> SurfaceStore::list() const {
    std::vector<StoredSurface> out;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [id, e] : entries_) out.push_back(e.info);
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.name < b.name; });
    return out;
}

size_t SurfaceStore::size() const {
    std::lock_guard lock(mutex_);
    return entries_.size();
}

} // namespace ddsimp::server
