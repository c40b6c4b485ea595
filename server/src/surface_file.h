// The server's file for one stored surface: "DDSURF1\n", a little-endian uint32 header length, a
// protobuf UploadBegin as the header (name, counts, fields), then the raw whole-mesh blob
// (docs/protocol.md, "Blobs"). The same format ships the built-in sample.
#pragma once

#include "ddsimp/ddsimp.h"

#include <filesystem>
#include <stdexcept>
#include <string>

namespace ddsimp::server {

class SurfaceFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SurfaceFile {
    std::string name;
    Surface surface;
};

// The file's bytes.
std::string encode_surface_file(const std::string& name, const Surface& surface);
// Throws SurfaceFileError naming the file and what is wrong.
SurfaceFile read_surface_file(const std::filesystem::path& path);
// Writes atomically: a temporary file in the same directory, flushed to disk, then renamed
// over `path`, and the directory flushed, so a crash leaves either no file or the whole file.
// Throws SurfaceFileError with the system's reason.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

} // namespace ddsimp::server
