// A surface file as `ddsimp` reads it: the bytes written to a file with the extension this target
// is built for (DDSIMP_FUZZ_EXTENSION: .vtk, .ply, .obj, .off or .stl), read with
// io::read_surface, then validated. Bad bytes must end in an IoError (or validate's InputError),
// never a crash or another exception; what is read has whole triangles and every field the right
// length (indices are checked by validate: read_surface returns the file as stored).
#include "fuzz_check.h"
#include "fuzz_temp_dir.h"

#include "ddsimp/io/surface_io.h"

#include <fstream>

using namespace ddsimp;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path = fuzz::temp_dir() + "/input" DDSIMP_FUZZ_EXTENSION;
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
        FUZZ_CHECK(out.good());
    }
    Surface surface;
    try {
        surface = io::read_surface(path);
    } catch (const io::IoError&) {
        return 0;
    }
    FUZZ_CHECK(surface.positions.size() % 3 == 0);
    FUZZ_CHECK(surface.triangles.size() % 3 == 0);
    for (const Field& f : surface.fields)
        FUZZ_CHECK(f.components >= 1 &&
                   f.values.size() == surface.vertex_count() * size_t(f.components));
    try {
        validate(surface);
    } catch (const InputError&) {
    }
    return 0;
}
