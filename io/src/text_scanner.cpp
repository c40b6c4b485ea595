#include "text_scanner.h"

#include <charconv>
#include <cstdio>

namespace ddsimp::io {

namespace {

// The white space of the "C" locale, which is what `>>` skips.
bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

} // namespace

void TextScanner::skip_space() {
    while (at_ < text_.size() && is_space(text_[at_])) {
        if (text_[at_] == '\n') ++line_;
        ++at_;
    }
}

std::optional<std::string_view> TextScanner::next() {
    skip_space();
    if (at_ == text_.size()) return std::nullopt;
    const size_t start = at_;
    while (at_ < text_.size() && !is_space(text_[at_])) ++at_;
    return text_.substr(start, at_ - start);
}

std::string_view TextScanner::rest_of_line() {
    const size_t start = at_;
    const size_t end = text_.find('\n', at_);
    if (end == std::string_view::npos) {
        at_ = text_.size();
        return text_.substr(start);
    }
    at_ = end + 1;
    ++line_;
    return text_.substr(start, end - start);
}

bool TextScanner::line_is_done() const {
    for (size_t i = at_; i < text_.size() && text_[i] != '\n'; ++i)
        if (!is_space(text_[i])) return false;
    return true;
}

bool is_float_word(std::string_view word) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1); // from_chars takes no '+'
    if (word.empty() || word[0] == '+') return false;
    for (char c : word)
        if (!((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+'))
            return false;
    float value = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    return error == std::errc() && end == word.data() + word.size();
}

bool is_integer_word(std::string_view word, int64_t& value) {
    if (!word.empty() && word[0] == '+') word.remove_prefix(1);
    if (word.empty() || word[0] == '+') return false;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    return error == std::errc() && end == word.data() + word.size();
}

std::string quoted(std::string_view word) {
    constexpr size_t kLongest = 24;
    std::string out = "'";
    for (size_t i = 0; i < word.size() && i < kLongest; ++i) {
        const unsigned char c = static_cast<unsigned char>(word[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02X", c);
            out += hex;
        }
    }
    if (word.size() > kLongest) out += "...";
    return out + "'";
}

} // namespace ddsimp::io
