// What the server writes into its log of a string a client chose (a client, surface, session or
// field name, a message that quotes one): nothing that can end the line, move the cursor or pass
// for another log line. Printable ASCII stays; a backslash, a double quote and every other byte
// (control characters, escape sequences, UTF-8) become \\, \" and \xNN; beyond `max_bytes` the rest
// is cut and counted.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ddsimp::server {

inline constexpr size_t kMaxLoggedBytes = 80;

std::string loggable(std::string_view text, size_t max_bytes = kMaxLoggedBytes);

// `text` as the inside of a JSON string (quotes, backslashes and control characters escaped).
std::string json_escaped(std::string_view text);

} // namespace ddsimp::server
