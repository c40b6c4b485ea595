#include "mpi_transfer.h"

#include <algorithm>

namespace ddsimp::mpi {

namespace {
constexpr size_t kMaxMessage = size_t(1) << 30;
constexpr int kTag = 7;
} // namespace

void send_bytes(const void* data, size_t size, int to) {
    const char* p = static_cast<const char*>(data);
    do { // at least one message, so that an empty array still pairs with its receive
        const size_t n = std::min(size, kMaxMessage);
        MPI_Send(p, int(n), MPI_BYTE, to, kTag, MPI_COMM_WORLD);
        p += n, size -= n;
    } while (size > 0);
}

void recv_bytes(void* data, size_t size, int from) {
    char* p = static_cast<char*>(data);
    do {
        const size_t n = std::min(size, kMaxMessage);
        MPI_Recv(p, int(n), MPI_BYTE, from, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        p += n, size -= n;
    } while (size > 0);
}

void send_string(const std::string& s, int to) {
    send_vector(std::vector<char>(s.begin(), s.end()), to);
}

std::string recv_string(int from) {
    const std::vector<char> v = recv_vector<char>(from);
    return std::string(v.begin(), v.end());
}

void send_surface(const Surface& s, int to) {
    send_vector(s.positions, to);
    send_vector(s.triangles, to);
    const uint64_t fields = s.fields.size();
    send_bytes(&fields, sizeof fields, to);
    for (const Field& f : s.fields) {
        send_string(f.name, to);
        const int32_t components = f.components, kind = int32_t(f.kind);
        send_bytes(&components, sizeof components, to);
        send_bytes(&kind, sizeof kind, to);
        send_vector(f.values, to);
    }
}

Surface recv_surface(int from) {
    Surface s;
    s.positions = recv_vector<float>(from);
    s.triangles = recv_vector<uint32_t>(from);
    uint64_t fields = 0;
    recv_bytes(&fields, sizeof fields, from);
    for (uint64_t i = 0; i < fields; ++i) {
        Field f;
        f.name = recv_string(from);
        int32_t components = 0, kind = 0;
        recv_bytes(&components, sizeof components, from);
        recv_bytes(&kind, sizeof kind, from);
        f.components = components;
        f.kind = FieldKind(kind);
        f.values = recv_vector<float>(from);
        s.fields.push_back(std::move(f));
    }
    return s;
}

bool all_ok(bool ok, std::string& message) {
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int mine = ok ? size : rank, first = size;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == size) return true;
    if (first != 0) {
        if (rank == first) send_string(message, 0);
        if (rank == 0) message = "rank " + std::to_string(first) + ": " + recv_string(first);
    }
    return false;
}

} // namespace ddsimp::mpi
