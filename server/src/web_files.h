// The browser renderer's files (--web-dir) as HTTP responses. A request never leaves the
// directory: not by "..", and not through a symbolic link that points out of it.
#pragma once

#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>

#include <string>

namespace ddsimp::server {

// The file of `target` (a request target, query allowed) in `dir` into `res`; 404 when there is
// none, or a page that says how to build the renderer when / is asked for and it is not there.
void serve_web_file(const std::string& dir, const std::string& target,
                    boost::beast::http::response<boost::beast::http::string_body>& res);

} // namespace ddsimp::server
