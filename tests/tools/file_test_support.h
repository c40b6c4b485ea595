// Shared by the tests of the file readers and writers: whole files as bytes, and the message a
// read or write fails with.
#pragma once

#include "ddsimp/io/surface_io.h"

#include <fstream>
#include <iterator>
#include <string>

namespace ddsimp::tools_test {

inline std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_text(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// The message of the IoError that `action` throws ("" if none is thrown).
template <class F> std::string io_error_of(F&& action) {
    try {
        action();
    } catch (const io::IoError& e) {
        return e.what();
    }
    return "";
}

} // namespace ddsimp::tools_test
