// The server's file for one stored surface: "DDSURF2\n", a little-endian uint32 header length, a
// protobuf UploadBegin as the header (name, counts, fields with their ranges), then the raw
// whole-mesh blob (docs/protocol.md, "Blobs"). The same format ships the built-in sample.
// "DDSURF1\n" files (no field ranges in the header) are read too.
#pragma once

#include "ddsimp/ddsimp.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace ddsimp::server {

class SurfaceFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SurfaceFile {
    std::string name;
    Surface surface;
};

// What a file says about its surface without reading it: enough to list it.
struct SurfaceFileHeader {
    std::string name;
    size_t vertices = 0, triangles = 0;
    struct Field {
        std::string name;
        int components = 1;
        FieldKind kind = FieldKind::Continuous;
        float min = 0, max = 0;
    };
    std::vector<Field> fields;
    bool ranges = false;   // the fields' min and max are known (a DDSURF2 file)
    size_t blob_bytes = 0; // the raw blob, as large as the surface in memory
};

// The file's bytes.
std::string encode_surface_file(const std::string& name, const Surface& surface);
// Throws SurfaceFileError naming the file and what is wrong.
SurfaceFile read_surface_file(const std::filesystem::path& path);
// Reads the header only, and checks that the file is as long as it says. Throws SurfaceFileError.
SurfaceFileHeader read_surface_header(const std::filesystem::path& path);
// Writes atomically: a temporary file in the same directory, flushed to disk, then renamed
// over `path`, and the directory flushed, so a crash leaves either no file or the whole file.
// Throws SurfaceFileError with the system's reason.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

} // namespace ddsimp::server
