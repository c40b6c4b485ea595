// The smallest complete renderer-side use of libddsimp-client: connect, pick a stored surface
// (or upload a small one), ask for two levels and print each as it arrives.
//
//   ddsimp_client_example [HOST:PORT] [TOKEN]
#include <ddsimp/client.h>

#include <cstdio>

int main(int argc, char** argv) {
    ddsimp::ConnectOptions options;
    options.client_name = "minimal renderer";
    options.kind = ddsimp::ClientKind::Desktop;
    try {
        if (argc > 1) ddsimp::parse_server_address(argv[1], options);
        if (argc > 2) options.token = argv[2];

        ddsimp::Client client;
        client.connect(options);

        // Use the first stored surface; upload a tetrahedron if there is none.
        std::string surface;
        const std::vector<ddsimp::SurfaceInfo> stored = client.list_surfaces();
        if (!stored.empty()) {
            surface = stored.front().surface;
        } else {
            ddsimp::Surface tetra;
            tetra.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
            tetra.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
            surface = client.upload(tetra, "tetrahedron").surface;
        }

        ddsimp::LevelRequest request;
        request.surface = surface;
        request.alpha = 0.5;
        request.keep = {0.5, 0.1}; // the server sends 0.1 first
        request.progressive = true;
        ddsimp::PendingRequest pending = client.request(request, [](const ddsimp::Level& level) {
            // A renderer would upload level.slots (progressive) or level.mesh to the GPU here.
            // A preview is a stand-in the server sends at once; the exact level replaces it.
            std::printf("%s keep=%g: %llu triangles, %zu vertices, %llu bytes%s\n",
                        level.preview ? "preview" : "level", level.keep,
                        static_cast<unsigned long long>(level.triangles), level.mesh.vertex_count(),
                        static_cast<unsigned long long>(level.wire_bytes),
                        level.refinement ? " (refinement)" : "");
        });
        pending.done.get(); // throws ddsimp::ClientError if the server refused
        std::printf("done: surface %s\n", surface.c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "minimal renderer: %s\n", e.what());
        return 1;
    }
}
