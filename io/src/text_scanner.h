// The words of a text mesh file as the C++ stream readers of OpenMesh and VTK see them (white
// space as `std::istream >>` skips it), with the line each word is on, so that the file checks
// can walk a file the way those readers will and name the line where it goes wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ddsimp::io {

class TextScanner {
public:
    explicit TextScanner(std::string_view text) : text_(text) {}

    // The next word, across line ends (like `in >> word`); nullopt at the end of the text.
    std::optional<std::string_view> next();
    // The rest of the current line, its line end consumed (like std::getline).
    std::string_view rest_of_line();
    // True if the rest of the current line is white space only.
    bool line_is_done() const;

    // The line (from 1) of the last word returned, or of where the scanner stands.
    size_t line() const { return line_; }
    size_t offset() const { return at_; }

private:
    void skip_space();

    std::string_view text_;
    size_t at_ = 0;
    size_t line_ = 1;
};

// `in >> x` with x a float would read all of `word` (digits, '.', an exponent; no "nan", "inf" or
// hexadecimal, which libstdc++ does not read either) and the value fits in a float.
bool is_float_word(std::string_view word);
// An integer: optional sign, then digits only. Sets `value` if it fits in 64 bits.
bool is_integer_word(std::string_view word, int64_t& value);

// `word` in quotes for an error message: cut to 24 characters, bytes that are not printable
// ASCII written as \xHH (fuzzed files are full of them).
std::string quoted(std::string_view word);

} // namespace ddsimp::io
