#include "web_files.h"

#include <boost/beast/http.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace ddsimp::server {
namespace http = boost::beast::http;
namespace fs = std::filesystem;

namespace {

std::string content_type(const std::string& path) {
    const auto ends = [&](const char* ext) {
        const std::string e(ext);
        return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
    };
    if (ends(".html")) return "text/html; charset=utf-8";
    if (ends(".js") || ends(".mjs")) return "text/javascript; charset=utf-8";
    if (ends(".css")) return "text/css; charset=utf-8";
    if (ends(".json")) return "application/json";
    if (ends(".wasm")) return "application/wasm";
    if (ends(".png")) return "image/png";
    if (ends(".svg")) return "image/svg+xml";
    if (ends(".ico")) return "image/x-icon";
    return "application/octet-stream";
}

// A request path mapped to a regular file inside the web directory (after following every
// symbolic link), or "" if there is none or it would leave the directory.
std::string web_file(const std::string& dir, std::string target) {
    target = target.substr(0, target.find_first_of("?#"));
    if (target.empty() || target[0] != '/' || target.find("..") != std::string::npos ||
        target.find('\\') != std::string::npos || target.find('\0') != std::string::npos)
        return "";
    if (target.back() == '/') target += "index.html";
    std::error_code ec;
    const fs::path root = fs::canonical(dir, ec);
    if (ec) return "";
    const fs::path file = fs::canonical(dir + target, ec);
    if (ec || !fs::is_regular_file(file, ec)) return "";
    // Inside: the root is a prefix of the resolved path, component by component.
    const auto [root_end, unused] =
        std::mismatch(root.begin(), root.end(), file.begin(), file.end());
    if (root_end != root.end()) return "";
    return file.string();
}

bool is_page_root(const std::string& target) {
    return target == "/" || target.rfind("/?", 0) == 0 || target == "/index.html";
}

std::string html_escape(const std::string& text) {
    std::string out;
    for (char ch : text) {
        if (ch == '&')
            out += "&amp;";
        else if (ch == '<')
            out += "&lt;";
        else if (ch == '>')
            out += "&gt;";
        else
            out += ch;
    }
    return out;
}

// What / shows when the browser renderer has not been built (or --web-dir points elsewhere).
std::string no_web_page(const std::string& dir) {
    const std::string where = dir.empty() ? std::string("no --web-dir is set")
                                          : "there is no index.html in " + html_escape(dir);
    return "<!doctype html><title>ddsimp-server</title><h1>ddsimp-server</h1>"
           "<p>The browser renderer is not here: " +
           where +
           ". Build it with <code>npm ci &amp;&amp; npm run build</code> in <code>web/</code> "
           "(<code>scripts/run.sh</code> does this) and start the server with "
           "<code>--web-dir web/dist</code>.</p><p>Endpoints: <a href=\"/healthz\">/healthz</a>, "
           "<a href=\"/metrics\">/metrics</a>, WebSocket <code>/ws</code>.</p>\n";
}

} // namespace

void serve_web_file(const std::string& dir, const std::string& target,
                    http::response<http::string_body>& res) {
    const std::string path = dir.empty() ? std::string() : web_file(dir, target);
    std::ifstream in;
    if (!path.empty()) in.open(path, std::ios::binary);
    if (!in.is_open()) {
        if (is_page_root(target)) {
            res.set(http::field::content_type, "text/html; charset=utf-8");
            res.body() = no_web_page(dir);
        } else {
            res.result(http::status::not_found);
            res.set(http::field::content_type, "text/plain");
            res.body() = "not found\n";
        }
        return;
    }
    res.set(http::field::content_type, content_type(path));
    // Vite names the files under assets/ by their content: they never change. The page
    // itself must be asked for again so a rebuilt renderer is picked up.
    res.set(http::field::cache_control,
            target.rfind("/assets/", 0) == 0 ? "public, max-age=31536000, immutable" : "no-cache");
    res.body().assign(std::istreambuf_iterator<char>(in), {});
}

} // namespace ddsimp::server
