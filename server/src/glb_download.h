// GET /surfaces/ID/level.glb: any level the server can serve, as binary glTF (protocol/glb.h),
// behind the server's token. Query parameters:
//   alpha=0.5  keep=0.5  strategy=edge|vertex  placement=least-error|midpoint|volume
//   data=least-error|interpolated (edge collapse's data at the new point)
//   terms=quadrics|paper  fields=A,B (the fields that drive the data term; default: all)
//   feature-angle=DEGREES (in (0, 180]; 180, the default: no feature edges)
//   field=NAME (the colours; default: the first continuous scalar that varies)  meshopt=1
//   token=T (or the header "Authorization: Bearer T")  session=NAME&key=K (a session's surfaces)
// The options not named are a Request's defaults (protocol/reduction_options.h), so a download
// and a request with the same values share one record and give the same level. The level is
// computed on the scheduler's pool, all downloads together taking turns as one client.
// The bytes of the files being built and sent are within --max-download-mb (DownloadBudget).
#pragma once

#include "ddsimp/ddsimp.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>

namespace ddsimp::server {

class HttpServer;

// The size of a level's .glb file without meshopt (which makes it smaller), for `vertices`,
// `triangles` and `components` field components per vertex: 12 bytes a triangle (32-bit
// indices), and per vertex 36 (position, normal, colour) plus 4 per field component; 64 KiB for
// its JSON.
uint64_t glb_file_bytes(uint64_t vertices, uint64_t triangles, uint64_t components);
// While it is built, a download holds this many times its file's size: the level, its normals
// and colours, the views' bytes and the file.
inline constexpr uint64_t kGlbBuildFactor = 4;

// The bytes of HTTP downloads being built and sent (level.glb files, and the web files), all
// together, within a limit (--max-download-mb). Any thread: a .glb is built on the pool and sent
// from the network thread.
class DownloadBudget {
public:
    explicit DownloadBudget(uint64_t limit) : limit_(limit) {}
    // Takes `bytes` more, or nothing and false when they would pass the limit.
    bool take(uint64_t bytes);
    void give_back(uint64_t bytes) { held_.fetch_sub(bytes); }
    uint64_t held() const { return held_.load(); }
    uint64_t limit() const { return limit_; }

private:
    const uint64_t limit_;
    std::atomic<uint64_t> held_{0};
};

// One download's share of the budget, given back when its last holder lets it go (the response
// written, or the download refused), on whatever thread that is. One thread at a time resizes.
class DownloadHold {
public:
    // The share of `bytes`, or null when they do not fit now.
    static std::shared_ptr<DownloadHold> take(std::shared_ptr<DownloadBudget> budget,
                                              uint64_t bytes);
    DownloadHold(std::shared_ptr<DownloadBudget> budget, uint64_t bytes)
        : budget_(std::move(budget)), bytes_(bytes) {}
    ~DownloadHold() { budget_->give_back(bytes_); }
    DownloadHold(const DownloadHold&) = delete;
    DownloadHold& operator=(const DownloadHold&) = delete;
    // Makes the share `bytes`; false (unchanged) when growing it would pass the limit.
    bool resize(uint64_t bytes);
    uint64_t bytes() const { return bytes_; }

private:
    std::shared_ptr<DownloadBudget> budget_;
    uint64_t bytes_;
};

// What a download answers, whatever carries it.
struct GlbAnswer {
    int status = 200;
    std::string content_type = "text/plain; charset=utf-8";
    std::string body;
    std::string filename; // set: sent as an attachment of that name
    // The body's share of the download budget: kept until the response is written.
    std::shared_ptr<const DownloadHold> hold;
};

// A parsed, checked download; `error` says what is wrong with it otherwise.
struct GlbDownload {
    std::string surface;
    Options options; // a Request's, with the query's reduction options
    float keep = 0.5f;
    std::string field;
    bool meshopt = false;
    std::string token;
    std::optional<std::string> session; // with `key`
    std::string key;
    std::string error;
};
// `target`: the request's path and query; `authorization`: its Authorization header, or "".
GlbDownload parse_glb_download(std::string_view target, std::string_view authorization);

// The scopes a download sees: the public one, and the session's if it names one.
std::set<std::string> glb_download_scopes(const GlbDownload& d);

// Adds the endpoint to `http` (its Service answers).
void route_glb_downloads(HttpServer& http);

} // namespace ddsimp::server
