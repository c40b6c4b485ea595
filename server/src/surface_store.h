// The stored surfaces: one file per surface in the data directory, named by its content hash,
// written atomically. Thread-safe: uploads are stored and surfaces loaded on the compute pool.
//
// Surfaces live on disk and come into memory on demand. At start only the index is read (ids,
// labels, sizes, fields: each file's header); load() reads a surface when a job needs it and
// keeps it within a memory bound, evicting the least recently used surface that nobody else
// holds. A job's shared_ptr keeps its surface alive, so a surface in use is never evicted; one
// that does not fit is the job's alone and goes when the job ends. The built-in sample is pinned
// in memory, outside the bound.
//
// Who may see a surface: its scopes. The public scope is every client's; a session's scope
// (session_scope) is its members'. A surface is stored once whatever scopes share it; each scope
// knows it by its own label, and a scope that does not have it never learns that it exists.
// The scopes of a surface are kept next to it (ID.scopes) and written before the surface, so a
// crash never leaves a surface without them; a surface file without one (written before scopes
// existed) is public.
#pragma once

#include "ddsimp/ddsimp.h"

#include <cstdint>
#include <filesystem>
#include <list>
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
    // `memory_bytes`: the most the resident surfaces (the sample aside) may take; `largest_bytes`:
    // the most one surface may take (a larger stored one is not read: load() throws).
    explicit SurfaceStore(std::filesystem::path dir, size_t memory_bytes = SIZE_MAX,
                          size_t largest_bytes = SIZE_MAX);

    struct Added {
        StoredSurface info;
        bool already_stored = false; // `scope` (or the public) had it already
    };
    // Stores a validated surface in `scope` (durably, before returning): the surface once, and
    // the scope added to those that see it. Throws SurfaceFileError if it cannot be written.
    // `token`: the name of the uploader's token, charged for it (quotas.h); empty: none.
    Added add(const std::string& name, Surface surface, const std::string& scope = kPublicScope,
              const std::string& token = "");
    // A public surface kept in memory only (the built-in sample).
    Added add_in_memory(const std::string& name, Surface surface);
    // Lets `scope` see a surface one of `scopes` sees (a member shows it to a session), under
    // the label it has there; false if none of `scopes` sees it. In memory: persist_scopes()
    // writes it (slow: not on the network thread).
    bool share(const std::string& id, const std::set<std::string>& scopes,
               const std::string& scope);
    // Writes who may see `id` to the data directory. Throws SurfaceFileError.
    void persist_scopes(const std::string& id);

    // Deleting (slow: not on the network thread). `token` takes back its upload of `id`, which
    // one of `scopes` must see; the surface leaves the store, its files first, once no token
    // that uploaded it is left, or at once when `one_user` (a server without per-user tokens).
    // A job that holds the surface keeps it. Throws SurfaceFileError if the files cannot be
    // changed.
    enum class Removal {
        NotFound, // none of `scopes` sees it
        NotOwner, // `token` did not upload it
        Pinned,   // the built-in sample
        Released, // the token's claim is gone; another token's keeps the surface
        Removed,
    };
    Removal remove(const std::string& id, const std::set<std::string>& scopes,
                   const std::string& token, bool one_user);
    // Whether storing `id` where `scope` sees it would charge anyone for it: false when the
    // surface is already stored and visible there (the public scope or `scope`).
    bool would_charge(const std::string& id, const std::string& scope) const;

    // The surface if one of `scopes` sees it, with the label of the first that does.
    std::optional<StoredSurface> find(const std::string& id,
                                      const std::set<std::string>& scopes) const;
    // The surface, from memory or read from its file (slow: not on the network thread); nullptr
    // if unknown. Throws SurfaceFileError if its file cannot be read or is not the surface it
    // names (the surface is then dropped from the index).
    std::shared_ptr<const Surface> load(const std::string& id);
    // What `scopes` see, by name, then id.
    std::vector<StoredSurface> list(const std::set<std::string>& scopes) const;
    size_t size() const;
    const std::filesystem::path& dir() const { return dir_; }

    // What a token uploaded, or a scope sees, for the quotas.
    struct Usage {
        size_t surfaces = 0;
        uint64_t bytes = 0;
    };
    Usage usage_of_token(const std::string& token) const;
    Usage usage_of_scope(const std::string& scope) const;

    // For /metrics.
    struct Residency {
        size_t resident = 0, resident_bytes = 0; // held in memory within the bound
        size_t pinned_bytes = 0;                 // the sample's
        size_t limit_bytes = 0;
        uint64_t loads = 0, evictions = 0, removals = 0;
    };
    Residency residency() const;

private:
    struct Entry {
        StoredSurface info;                        // name unset: see labels
        std::map<std::string, std::string> labels; // scope -> the surface's label there
        std::set<std::string> tokens;              // the names of the tokens that uploaded it
        size_t bytes = 0;                          // in memory
        bool pinned = false;                       // in memory only (the sample)
        std::shared_ptr<const Surface> surface;    // resident (held by the store), or null
        std::weak_ptr<const Surface> in_use;       // still held by a job after its eviction
        std::list<std::string>::iterator recent;   // its place in recent_ while resident
    };
    // Makes `surface` resident for `e` if it fits, evicting the least recently used surfaces
    // nobody else holds; otherwise leaves it to its holders. Under mutex_.
    void keep(Entry& e, const std::string& id, std::shared_ptr<const Surface> surface);
    void evict(Entry& e);
    // Reads and checks the file of `id`; throws SurfaceFileError.
    Surface read(const std::string& id) const;
    Added insert(const std::string& id, const std::string& name, Surface surface,
                 const std::string& scope, const std::string& token, bool write);
    // Writes the scopes file of `id`: its labels and tokens (under files_mutex_).
    void write_scopes(const std::string& id, const std::map<std::string, std::string>& labels,
                      const std::set<std::string>& tokens);
    static std::optional<StoredSurface> visible(const Entry& e,
                                                const std::set<std::string>& scopes);

    std::filesystem::path dir_;
    mutable std::mutex mutex_; // entries_
    std::mutex files_mutex_;   // writes, so that concurrent scope changes reach the disk in order
    std::map<std::string, Entry> entries_;
    std::list<std::string> recent_; // resident unpinned surfaces, the most recently used first
    size_t memory_limit_;
    size_t largest_bytes_;
    size_t resident_bytes_ = 0, pinned_bytes_ = 0;
    uint64_t loads_ = 0, evictions_ = 0, removals_ = 0;
};

// The bytes a surface takes in memory (its arrays).
size_t surface_bytes(const Surface& s);

StoredSurface describe_surface(const std::string& id, const std::string& name, const Surface& s);

} // namespace ddsimp::server
