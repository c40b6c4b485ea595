// A member of a ddsimp-server session, as a web or VR renderer would be: joins, prints "joined",
// then waits for the session's first mesh and prints it as one line
//   mesh triangles=N vertices=M fields=NAME:COMPONENTS,...
// Exit 0 after a mesh; 1 if none came within the timeout or the server refused.
// Usage: ddsimp_session_watch HOST:PORT TOKEN SESSION KEY TIMEOUT_SECONDS
#include "ddsimp/client.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) {
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s HOST:PORT TOKEN SESSION KEY TIMEOUT_SECONDS\n", argv[0]);
        return 2;
    }
    try {
        ddsimp::ConnectOptions options;
        ddsimp::parse_server_address(argv[1], options);
        options.token = argv[2];
        options.client_name = "session-watch";
        options.kind = ddsimp::ClientKind::VR;
        ddsimp::Client client;
        client.connect(options);
        client.join_session(argv[3], argv[4]);
        std::printf("joined\n");
        std::fflush(stdout);
        const auto until =
            std::chrono::steady_clock::now() + std::chrono::seconds(std::stoi(argv[5]));
        while (std::chrono::steady_clock::now() < until) {
            auto event = client.next_session_event(std::chrono::milliseconds(200));
            if (!event || event->kind != ddsimp::SessionEvent::Kind::Mesh) continue;
            const ddsimp::Surface& mesh = event->mesh.mesh;
            std::string fields;
            for (const auto& f : mesh.fields)
                fields += (fields.empty() ? "" : ",") + f.name + ":" + std::to_string(f.components);
            std::printf("mesh triangles=%zu vertices=%zu fields=%s\n", mesh.triangle_count(),
                        mesh.vertex_count(), fields.c_str());
            return 0;
        }
        std::fprintf(stderr, "no mesh within %s s\n", argv[5]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "session-watch: %s\n", e.what());
    }
    return 1;
}
