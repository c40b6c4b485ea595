// Writes a surface file in the server's store format from any file `ddsimp` reads: how
// data/SurfaceVectors.ddsurf, the server's built-in sample, is made from data/SurfaceVectors.vtk.
//   ddsimp-make-sample IN OUT NAME
#include "ddsimp/io/surface_io.h"
#include "surface_file.h"

#include <iostream>

int main(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: ddsimp-make-sample IN OUT NAME\n";
        return 2;
    }
    try {
        ddsimp::Surface s = ddsimp::io::read_surface(argv[1]);
        ddsimp::validate(s);
        ddsimp::server::write_file_atomically(argv[2],
                                              ddsimp::server::encode_surface_file(argv[3], s));
    } catch (const std::exception& e) {
        std::cerr << "ddsimp-make-sample: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
