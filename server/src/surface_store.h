// The stored surfaces: one file per surface in the data directory, named by its content hash,
// written atomically and reloaded at start. Thread-safe: uploads are stored and surfaces loaded
// on the compute pool.
//
// Who may see a surface: its scopes. The public scope is every client's; a session's scope
// (session_scope) is its members'. A surface is stored once whatever scopes share it; each scope
// knows it by its own label, and a scope that does not have it never learns that it exists.
// The scopes of a surface are kept next to it (ID.scopes) and written before the surface, so a
// crash never leaves a surface without them; a surface file without one (written before scopes
// existed) is public.
#pragma once

#include "ddsimp/ddsimp.h"

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace ddsimp::server {

// The public scope; every client has it.
inline const std::string kPublicScope;
// A session's scope: hex SHA-256 of its name and key (length-prefixed, so no two pairs collide).
std::string session_scope(const std::string& name, const std::string& key);

struct StoredSurface {
    std::string id;   // hex SHA-256 of the validated surface (protocol::surface_hash)
    std::string name; // its label in the scope that asked
    size_t vertices = 0;
    size_t triangles = 0;
    struct FieldRange {
        std::string name;
        int components = 1;
        FieldKind kind = FieldKind::Continuous;
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
        bool already_stored = false; // `scope` (or the public) had it already
    };
    // Stores a validated surface in `scope` (durably, before returning): the surface once, and
    // the scope added to those that see it. Throws SurfaceFileError if it cannot be written.
    Added add(const std::string& name, Surface surface, const std::string& scope = kPublicScope);
    // A public surface kept in memory only (the built-in sample).
    Added add_in_memory(const std::string& name, Surface surface);
    // Lets `scope` see a surface one of `scopes` sees (a member shows it to a session), under
    // the label it has there; false if none of `scopes` sees it. In memory: persist_scopes()
    // writes it (slow: not on the network thread).
    bool share(const std::string& id, const std::set<std::string>& scopes,
               const std::string& scope);
    // Writes who may see `id` to the data directory. Throws SurfaceFileError.
    void persist_scopes(const std::string& id);

    // The surface if one of `scopes` sees it, with the label of the first that does.
    std::optional<StoredSurface> find(const std::string& id,
                                      const std::set<std::string>& scopes) const;
    std::shared_ptr<const Surface> load(const std::string& id) const; // nullptr if unknown
    // What `scopes` see, by name, then id.
    std::vector<StoredSurface> list(const std::set<std::string>& scopes) const;
    size_t size() const;
    const std::filesystem::path& dir() const { return dir_; }

private:
    struct Entry {
        StoredSurface info;                        // name unset: see labels
        std::map<std::string, std::string> labels; // scope -> the surface's label there
        std::shared_ptr<const Surface> surface;
    };
    Added insert(const std::string& id, const std::string& name, Surface surface,
                 const std::string& scope, bool write);
    // Writes the scopes file of `id` with `labels` (under files_mutex_).
    void write_scopes(const std::string& id, const std::map<std::string, std::string>& labels);
    static std::optional<StoredSurface> visible(const Entry& e,
                                                const std::set<std::string>& scopes);

    std::filesystem::path dir_;
    mutable std::mutex mutex_; // entries_
    std::mutex files_mutex_;   // writes, so that concurrent scope changes reach the disk in order
    std::map<std::string, Entry> entries_;
};

StoredSurface describe_surface(const std::string& id, const std::string& name, const Surface& s);

} // namespace ddsimp::server
