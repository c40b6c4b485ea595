// The stored surfaces: one file per surface in the data directory, named by its content hash,
// written atomically and reloaded at start. Thread-safe: uploads are stored and surfaces loaded
// on the compute pool.
#pragma once

#include "ddsimp/ddsimp.h"

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace ddsimp::server {

struct StoredSurface {
    std::string id; // hex SHA-256 of the validated surface (protocol::surface_hash)
    std::string name;
    size_t vertices = 0;
    size_t triangles = 0;
    struct FieldRange {
        std::string name;
        int components = 1;
        float min = 0, max = 0;
    };
    std::vector<FieldRange> fields;
};

class SurfaceStore {
public:
    // Loads every complete surface file of `dir` (creating it if missing). Leftover temporary
    // files of an interrupted write are removed; a file that does not load is logged and skipped.
    // Throws std::runtime_error if the directory cannot be created or read.
    explicit SurfaceStore(std::filesystem::path dir);

    struct Added {
        StoredSurface info;
        bool already_stored = false;
    };
    // Stores a validated surface (durably, before returning) unless one with its id exists.
    // Throws SurfaceFileError if it cannot be written.
    Added add(const std::string& name, Surface surface);
    // A surface kept in memory only (the built-in sample when no data directory is writable).
    Added add_in_memory(const std::string& name, Surface surface);

    std::optional<StoredSurface> find(const std::string& id) const;
    std::shared_ptr<const Surface> load(const std::string& id) const; // nullptr if unknown
    std::vector<StoredSurface> list() const;                          // by name, then id
    size_t size() const;
    const std::filesystem::path& dir() const { return dir_; }

private:
    struct Entry {
        StoredSurface info;
        std::shared_ptr<const Surface> surface;
    };
    Added insert(const std::string& id, const std::string& name, Surface surface, bool write);

    std::filesystem::path dir_;
    mutable std::mutex mutex_;
    std::map<std::string, Entry> entries_;
};

StoredSurface describe_surface(const std::string& id, const std::string& name, const Surface& s);

} // namespace ddsimp::server
