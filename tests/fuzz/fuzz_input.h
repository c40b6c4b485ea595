// Reads typed values off the front of a fuzz input. Past the end every read yields zeros, so a
// short input is still a valid (if boring) one and the fuzzer never needs a length check.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace ddsimp::fuzz {

class FuzzInput {
public:
    FuzzInput(const uint8_t* data, size_t size)
        : bytes_(reinterpret_cast<const char*>(data), size) {}

    template <class T> T take() {
        static_assert(std::is_trivially_copyable_v<T>);
        T value{};
        const size_t n = std::min(sizeof(T), bytes_.size());
        std::memcpy(&value, bytes_.data(), n);
        bytes_.remove_prefix(n);
        return value;
    }

    // A value in [0, bound) (0 when bound is 0).
    uint64_t take_below(uint64_t bound) { return bound == 0 ? 0 : take<uint64_t>() % bound; }

    std::string_view take_bytes(size_t n) {
        n = std::min(n, bytes_.size());
        const std::string_view out = bytes_.substr(0, n);
        bytes_.remove_prefix(n);
        return out;
    }

    // A length-prefixed (16-bit) string.
    std::string_view take_chunk() { return take_bytes(take<uint16_t>()); }

    std::string_view rest() {
        const std::string_view out = bytes_;
        bytes_ = {};
        return out;
    }
    bool empty() const { return bytes_.empty(); }

private:
    std::string_view bytes_;
};

} // namespace ddsimp::fuzz
