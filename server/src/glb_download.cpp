// The .glb download: its query, its route, and Service::download_glb (declared in service.h).
#include "glb_download.h"

#include "client_limits.h"
#include "http_server.h"
#include "log_text.h"
#include "service.h"

#include "ddsimp/protocol/glb.h"
#include "ddsimp/protocol/reduction_options.h"

#include <boost/beast/http/field.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>

namespace ddsimp::server {

namespace {

constexpr std::string_view kPrefix = "/surfaces/";
constexpr std::string_view kSuffix = "/level.glb";

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// %XX and '+' decoded; nullopt for a broken escape.
std::optional<std::string> url_decode(std::string_view s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '+') {
            out += ' ';
        } else if (s[i] == '%') {
            if (i + 2 >= s.size()) return std::nullopt;
            const int hi = hex_digit(s[i + 1]), lo = hex_digit(s[i + 2]);
            if (hi < 0 || lo < 0) return std::nullopt;
            out += char(16 * hi + lo);
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

std::optional<double> number(const std::string& text) {
    double x = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x))
        return std::nullopt;
    return x;
}

// A plain-text answer (an error): `text` and a newline.
GlbAnswer text_answer(int status, const std::string& text) {
    GlbAnswer a;
    a.status = status;
    a.body = text + "\n";
    return a;
}

} // namespace

uint64_t glb_file_bytes(uint64_t vertices, uint64_t triangles, uint64_t components) {
    return 12 * triangles + vertices * (36 + 4 * components) + (64u << 10);
}

bool DownloadBudget::take(uint64_t bytes) {
    uint64_t now = held_.load();
    do {
        if (bytes > limit_ || now > limit_ - bytes) return false;
    } while (!held_.compare_exchange_weak(now, now + bytes));
    return true;
}

std::shared_ptr<DownloadHold> DownloadHold::take(std::shared_ptr<DownloadBudget> budget,
                                                 uint64_t bytes) {
    if (!budget->take(bytes)) return nullptr;
    return std::make_shared<DownloadHold>(std::move(budget), bytes);
}

bool DownloadHold::resize(uint64_t bytes) {
    if (bytes > bytes_ && !budget_->take(bytes - bytes_)) return false;
    if (bytes < bytes_) budget_->give_back(bytes_ - bytes);
    bytes_ = bytes;
    return true;
}

GlbDownload parse_glb_download(std::string_view target, std::string_view authorization) {
    GlbDownload d;
    const size_t q = target.find('?');
    const std::string_view path = target.substr(0, q);
    if (!(path.size() > kPrefix.size() + kSuffix.size() && path.starts_with(kPrefix) &&
          path.ends_with(kSuffix))) {
        d.error = "no such path: " + std::string(path) + " (/surfaces/ID/level.glb)";
        return d;
    }
    d.surface =
        std::string(path.substr(kPrefix.size(), path.size() - kPrefix.size() - kSuffix.size()));
    if (d.surface.find('/') != std::string::npos) {
        d.error = "no such path: " + std::string(path) + " (/surfaces/ID/level.glb)";
        return d;
    }
    std::map<std::string, std::string> params;
    std::string_view rest = q == std::string_view::npos ? std::string_view() : target.substr(q + 1);
    while (!rest.empty()) {
        const size_t amp = rest.find('&');
        const std::string_view pair = rest.substr(0, amp);
        rest = amp == std::string_view::npos ? std::string_view() : rest.substr(amp + 1);
        if (pair.empty()) continue;
        const size_t eq = pair.find('=');
        const auto name = url_decode(pair.substr(0, eq));
        const auto value =
            url_decode(eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1));
        if (!name || !value) {
            d.error = "a broken %-escape in the query";
            return d;
        }
        params[*name] = *value;
    }
    // The query's options; they then travel as a Request carries them (protocol's one mapping,
    // which also checks them), so a download and a request with the same values share a record.
    Options options;
    for (const auto& [name, value] : params) {
        if (name == "alpha" || name == "keep") {
            const auto x = number(value);
            const bool ok = x && (name == "alpha" ? *x >= 0 && *x <= 1 : *x > 0 && *x <= 1);
            if (!ok) {
                d.error = name + "=" + value + " is not a number in " +
                          (name == "alpha" ? "[0, 1]" : "(0, 1]");
                return d;
            }
            if (name == "alpha")
                options.alpha = *x;
            else
                d.keep = float(*x);
        } else if (name == "strategy") {
            if (value != "edge" && value != "vertex") {
                d.error = "strategy=" + value + ": edge or vertex";
                return d;
            }
            options.strategy = value == "edge" ? Strategy::EdgeCollapse : Strategy::VertexRemoval;
        } else if (name == "placement") {
            if (value == "least-error")
                options.placement = Placement::LeastError;
            else if (value == "midpoint")
                options.placement = Placement::Midpoint;
            else if (value == "volume")
                options.placement = Placement::VolumePreserving;
            else {
                d.error = "placement=" + value + ": least-error, midpoint or volume";
                return d;
            }
        } else if (name == "data") {
            if (value != "least-error" && value != "interpolated") {
                d.error = "data=" + value + ": least-error or interpolated";
                return d;
            }
            options.data_placement =
                value == "interpolated" ? DataPlacement::Interpolated : DataPlacement::LeastError;
        } else if (name == "terms") {
            if (value != "quadrics" && value != "paper") {
                d.error = "terms=" + value + ": quadrics or paper";
                return d;
            }
            options.terms = value == "paper" ? Terms::AngleDeficitGradient : Terms::ErrorQuadrics;
        } else if (name == "fields") {
            // The fields that drive the data term, comma-separated (empty: all), within a
            // request's limits.
            for (size_t at = 0; at <= value.size();) {
                const size_t comma = std::min(value.find(',', at), value.size());
                if (comma > at) options.gradient_fields.push_back(value.substr(at, comma - at));
                at = comma + 1;
            }
            if (options.gradient_fields.size() > kMaxFields) {
                d.error = "fields: more than " + std::to_string(kMaxFields) + " fields";
                return d;
            }
            for (const std::string& f : options.gradient_fields)
                if (f.size() > kMaxNameBytes) {
                    d.error = "fields: a field name of " + std::to_string(f.size()) +
                              " bytes (at most " + std::to_string(kMaxNameBytes) + ")";
                    return d;
                }
        } else if (name == "feature-angle") {
            // A request cannot say 0 (on the wire it means none), so the range is (0, 180].
            const auto x = number(value);
            if (!x || *x <= 0 || *x > 180) {
                d.error = "feature-angle=" + value + " is not a number of degrees in (0, 180]";
                return d;
            }
            options.feature_angle = *x;
        } else if (name == "field") {
            d.field = value;
        } else if (name == "meshopt") {
            d.meshopt = value == "1" || value == "true";
        } else if (name == "token") {
            d.token = value;
        } else if (name == "session") {
            d.session = value;
        } else if (name == "key") {
            d.key = value;
        } else {
            d.error = "unknown parameter '" + name +
                      "' (alpha, keep, strategy, placement, data, terms, fields, feature-angle, "
                      "field, meshopt, token, session, key)";
            return d;
        }
    }
    v1::Request request;
    protocol::set_options(request, options);
    try {
        d.options = protocol::options_from(request);
    } catch (const InputError& e) {
        d.error = e.what();
        return d;
    }
    constexpr std::string_view kBearer = "Bearer ";
    if (d.token.empty() && authorization.starts_with(kBearer))
        d.token = std::string(authorization.substr(kBearer.size()));
    return d;
}

std::set<std::string> glb_download_scopes(const GlbDownload& d) {
    std::set<std::string> scopes{kPublicScope};
    if (d.session) scopes.insert(session_scope(*d.session, d.key));
    return scopes;
}

void route_glb_downloads(HttpServer& http) {
    http.route_later(std::string(kPrefix), [&service = http.service()](const HttpRequest& request,
                                                                       HttpResponse res,
                                                                       HttpReply reply) {
        namespace http = boost::beast::http;
        const auto target = request.target();
        const auto authorization = request[http::field::authorization];
        const GlbDownload d =
            parse_glb_download(std::string_view(target.data(), target.size()),
                               std::string_view(authorization.data(), authorization.size()));
        service.download_glb(d,
                             [res = std::move(res), reply = std::move(reply)](GlbAnswer a) mutable {
                                 res.result(http::status(a.status));
                                 res.set(http::field::content_type, a.content_type);
                                 if (a.status == 503) res.set(http::field::retry_after, "10");
                                 if (!a.filename.empty())
                                     res.set(http::field::content_disposition,
                                             "attachment; filename=\"" + a.filename + "\"");
                                 res.body() = std::move(a.body);
                                 reply(std::move(res), std::move(a.hold));
                             });
    });
}

void Service::download_glb(const GlbDownload& d, std::function<void(GlbAnswer)> done) {
    const auto refuse = [&](int status, const std::string& why) { done(text_answer(status, why)); };
    if (!d.error.empty()) return refuse(d.error.starts_with("no such path") ? 404 : 400, d.error);
    if (tokens_.required() && !tokens_.match(d.token))
        return refuse(401, d.token.empty() ? "this server needs a token (token=T)" : "wrong token");
    const auto stored = store_.find(d.surface, glb_download_scopes(d));
    if (!stored) return refuse(404, "no surface " + d.surface);

    ReductionParams params{d.surface, d.options};
    const std::string key = protocol::result_key(params.surface, params.options);
    protocol::GlbOptions options;
    options.colour_field = d.field;
    options.meshopt = d.meshopt;
    options.name = stored->name.empty() ? d.surface : stored->name;
    char level[64];
    std::snprintf(level, sizeof level, "-alpha%g-keep%g", d.options.alpha, double(d.keep));
    const std::string filename = d.surface.substr(0, 12) + level + ".glb";
    const size_t depth = protocol::target_for_keep(d.keep, stored->triangles);

    // Its share of --max-download-mb while it is built: its file's size at the level's share of
    // the vertices, times the build's copies. A level that can never fit is refused for good,
    // one that does not fit beside the others' for now.
    uint64_t components = 0;
    for (const StoredSurface::FieldRange& f : stored->fields) components += uint64_t(f.components);
    const uint64_t vertices =
        stored->triangles ? uint64_t(stored->vertices) * depth / stored->triangles : 0;
    const uint64_t building = kGlbBuildFactor * glb_file_bytes(vertices, depth, components);
    const auto mib = [](uint64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20); };
    if (building > downloads_->limit()) {
        ++metrics_.downloads_refused;
        return refuse(413, "this level's .glb takes about " + mib(building) +
                               " MiB to build, more than the " + mib(downloads_->limit()) +
                               " MiB the server allows for downloads (--max-download-mb); ask "
                               "for a coarser level (a smaller keep)");
    }
    std::shared_ptr<DownloadHold> hold = DownloadHold::take(downloads_, building);
    if (!hold) {
        ++metrics_.downloads_refused;
        return refuse(503, "the server is building and sending " + mib(downloads_->held()) +
                               " MiB of downloads, and this one's " + mib(building) +
                               " MiB would pass its " + mib(downloads_->limit()) +
                               " MiB (--max-download-mb); try again later");
    }

    // The download waits for the record as a request does: a computation it shares goes on.
    const std::string waiter = "download/" + std::to_string(next_download_++);
    const CancelFlag cancelled = computations_.wait(key, waiter);
    auto finish = std::make_shared<std::function<void(GlbAnswer)>>(std::move(done));
    const bool queued = compute(kDownloadsClient, [this, params, key, depth, keep = d.keep, options,
                                                   filename, waiter, cancelled,
                                                   ranges = stored->fields, finish,
                                                   hold]() mutable {
        GlbAnswer answer;
        try {
            bool computed = false;
            auto rec = record_for(reductions_, params, key, depth, *cancelled, &computed);
            const ProgressiveRecord& record = rec->record;
            const Surface s = record.after(
                record.operations_for(protocol::target_for_keep(keep, record.triangles_in())));
            // The field is chosen on the whole surface, and a scalar is coloured over the whole
            // surface's range, as the page colours it.
            if (const Field* f =
                    protocol::glb_colour_field(record.vertices(), options.colour_field))
                options.colour_field = f->name;
            for (const auto& f : ranges)
                if (f.name == options.colour_field && f.components == 1)
                    options.colour_range = protocol::ColourRange{f.min, f.max};
            answer.content_type = "model/gltf-binary";
            answer.body = protocol::write_glb(s, options);
            answer.filename = filename;
        } catch (const protocol::GlbError& e) {
            answer = text_answer(400, e.what());
        } catch (const InputError& e) { // options the surface cannot take, e.g. an unknown field
            answer = text_answer(400, e.what());
        } catch (const std::invalid_argument& e) {
            answer = text_answer(404, e.what());
        } catch (const std::exception& e) {
            spdlog::warn("GET {}.glb: {}", loggable(params.surface), loggable(e.what()));
            answer = text_answer(422, e.what());
        }
        // Until it is sent, the download holds its file (more than estimated when the level
        // stopped short of its target: then it must fit beside the others, or it is not sent).
        if (answer.status == 200 && !hold->resize(answer.body.size())) {
            ++metrics_.downloads_refused;
            answer = text_answer(503, "the level's .glb of " +
                                          std::to_string((answer.body.size() >> 20) + 1) +
                                          " MiB does not fit beside the downloads being sent "
                                          "(--max-download-mb); try again later");
        }
        if (answer.status == 200) answer.hold = hold;
        hold.reset(); // an error's share goes at once
        boost::asio::post(io_, [this, key, waiter, finish, answer = std::move(answer)]() mutable {
            computations_.leave(key, waiter);
            // The callback holds the HTTP session (and its place among the clients): it is let
            // go here, on the network thread, whichever thread drops `finish` last.
            auto reply = std::move(*finish);
            *finish = nullptr;
            reply(std::move(answer));
        });
    });
    if (!queued) {
        computations_.leave(key, waiter);
        (*finish)(text_answer(503, "too many downloads waiting; try again later"));
    }
}

} // namespace ddsimp::server
