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
#pragma once

#include "ddsimp/ddsimp.h"

#include <optional>
#include <set>
#include <string>
#include <string_view>

namespace ddsimp::server {

class HttpServer;

// What a download answers, whatever carries it.
struct GlbAnswer {
    int status = 200;
    std::string content_type = "text/plain; charset=utf-8";
    std::string body;
    std::string filename; // set: sent as an attachment of that name
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
