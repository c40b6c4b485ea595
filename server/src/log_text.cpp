#include "log_text.h"

#include <algorithm>
#include <cstdio>

namespace ddsimp::server {

std::string loggable(std::string_view text, size_t max_bytes) {
    std::string out;
    out.reserve(std::min(text.size(), max_bytes) + 8);
    const size_t shown = std::min(text.size(), max_bytes);
    for (size_t i = 0; i < shown; ++i) {
        const unsigned char ch = static_cast<unsigned char>(text[i]);
        if (ch == '\\' || ch == '"') {
            out += '\\';
            out += char(ch);
        } else if (ch >= 0x20 && ch < 0x7f) {
            out += char(ch);
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02x", ch);
            out += hex;
        }
    }
    if (shown < text.size()) out += "...(" + std::to_string(text.size() - shown) + " more bytes)";
    return out;
}

std::string json_escaped(std::string_view text) {
    std::string out;
    out.reserve(text.size() + 8);
    for (char c : text) {
        const unsigned char ch = static_cast<unsigned char>(c);
        if (ch == '\\' || ch == '"') {
            out += '\\';
            out += c;
        } else if (ch == '\n') {
            out += "\\n";
        } else if (ch < 0x20 || ch == 0x7f) {
            char hex[7];
            std::snprintf(hex, sizeof hex, "\\u%04x", ch);
            out += hex;
        } else {
            out += c;
        }
    }
    return out;
}

} // namespace ddsimp::server
