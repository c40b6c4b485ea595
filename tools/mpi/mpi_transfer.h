// Moving surfaces and arrays between ranks, and agreeing on failure, with plain MPI point-to-point
// messages on MPI_COMM_WORLD. Every call has a matching call on the other rank(s).
#pragma once

#include "ddsimp/ddsimp.h"

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ddsimp::mpi {

// Raw bytes, in messages of at most 1 GiB (MPI counts are int).
void send_bytes(const void* data, size_t size, int to);
void recv_bytes(void* data, size_t size, int from);

template <class T> void send_vector(const std::vector<T>& v, int to) {
    const uint64_t n = v.size();
    send_bytes(&n, sizeof n, to);
    send_bytes(v.data(), n * sizeof(T), to);
}
template <class T> std::vector<T> recv_vector(int from) {
    uint64_t n = 0;
    recv_bytes(&n, sizeof n, from);
    std::vector<T> v(n);
    recv_bytes(v.data(), n * sizeof(T), from);
    return v;
}

void send_string(const std::string& s, int to);
std::string recv_string(int from);

void send_surface(const Surface& s, int to);
Surface recv_surface(int from);

// Collective: true if every rank passed ok = true. Otherwise false on every rank, and on rank 0
// `message` holds the message of the lowest failing rank (prefixed "rank N: " for N > 0).
bool all_ok(bool ok, std::string& message);

} // namespace ddsimp::mpi
