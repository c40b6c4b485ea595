// The server's own surface file (the store's files and the built-in sample, read at start):
// bad bytes must end in a SurfaceFileError naming the file, and what is read must have every
// index in range and every field the right length.
#include "fuzz_check.h"
#include "fuzz_temp_dir.h"

#include "surface_file.h"

#include <fstream>

using namespace ddsimp;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path = fuzz::temp_dir() + "/input.ddsurf";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
        FUZZ_CHECK(out.good());
    }
    server::SurfaceFile file;
    try {
        file = server::read_surface_file(path);
    } catch (const server::SurfaceFileError&) {
        return 0;
    }
    const Surface& s = file.surface;
    FUZZ_CHECK(s.positions.size() % 3 == 0 && s.triangles.size() % 3 == 0);
    for (uint32_t v : s.triangles) FUZZ_CHECK(v < s.vertex_count());
    for (const Field& f : s.fields)
        FUZZ_CHECK(f.components >= 1 && f.values.size() == s.vertex_count() * size_t(f.components));
    return 0;
}
