// Writes a surface file in the server's store format, either from any surface file `ddsimp` reads
// or as an isosurface of a volume with its other fields carried on. This is how the server's
// samples in data/ are made (data/README.md has the exact commands):
//   ddsimp-make-sample IN OUT NAME
//   ddsimp-make-sample --isosurface FIELD VALUE RESAMPLE CARRY VOLUME OUT NAME
// (CARRY: the fields carried onto the isosurface, comma-separated; the contoured field itself is
// constant there.)
#include "ddsimp/io/isosurface.h"
#include "ddsimp/io/surface_io.h"
#include "surface_file.h"

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage = "usage: ddsimp-make-sample IN OUT NAME\n"
                               "       ddsimp-make-sample --isosurface FIELD VALUE RESAMPLE CARRY "
                               "VOLUME OUT NAME\n";

ddsimp::Surface make_surface(const std::vector<std::string>& args) {
    if (args[0] != "--isosurface") return ddsimp::io::read_surface(args[0]);
    ddsimp::io::IsosurfaceOptions options;
    options.field = args[1];
    options.value = std::stod(args[2]);
    options.resample = std::stoi(args[3]);
    std::stringstream carry(args[4]);
    for (std::string field; std::getline(carry, field, ',');) options.carry.push_back(field);
    return ddsimp::io::extract_isosurface(args[5], options);
}

} // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    const bool isosurface = !args.empty() && args[0] == "--isosurface";
    if (args.size() != (isosurface ? 8u : 3u)) {
        std::cerr << kUsage;
        return 2;
    }
    try {
        ddsimp::Surface s = make_surface(args);
        ddsimp::validate(s);
        const std::string& out = args[args.size() - 2];
        ddsimp::server::write_file_atomically(out,
                                              ddsimp::server::encode_surface_file(args.back(), s));
        std::cout << out << ": " << s.triangle_count() << " triangles, " << s.vertex_count()
                  << " vertices\n";
    } catch (const std::exception& e) {
        std::cerr << "ddsimp-make-sample: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
