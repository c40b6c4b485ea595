#include "ddsimp/protocol/content_hash.h"

#include <openssl/evp.h>

#include <algorithm>
#include <bit>
#include <memory>
#include <stdexcept>

namespace ddsimp::protocol {
namespace {

class Sha256 {
public:
    Sha256() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
        if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1)
            throw std::runtime_error("OpenSSL cannot start a SHA-256 digest");
    }
    void add(const void* data, size_t bytes) { EVP_DigestUpdate(ctx_.get(), data, bytes); }
    void add_u64(uint64_t v) {
        unsigned char b[8];
        for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
        add(b, 8);
    }
    std::string hex() {
        unsigned char digest[EVP_MAX_MD_SIZE];
        unsigned int n = 0;
        EVP_DigestFinal_ex(ctx_.get(), digest, &n);
        static constexpr char kDigits[] = "0123456789abcdef";
        std::string out;
        for (unsigned int i = 0; i < n; ++i) {
            out += kDigits[digest[i] >> 4];
            out += kDigits[digest[i] & 15];
        }
        return out;
    }

private:
    std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

static_assert(std::endian::native == std::endian::little, "the hashed layout is little endian");

} // namespace

std::string sha256_hex(std::string_view bytes) {
    Sha256 h;
    h.add(bytes.data(), bytes.size());
    return h.hex();
}

std::string surface_hash(const Surface& s) {
    // A surface whose fields are all continuous hashes as before kinds existed (the ids of
    // stored surfaces stay); any other kind makes it a different surface, with every kind hashed.
    const bool kinds = std::any_of(s.fields.begin(), s.fields.end(),
                                   [](const Field& f) { return f.kind != FieldKind::Continuous; });
    Sha256 h;
    h.add(kinds ? "ddsimp-surface-2" : "ddsimp-surface-1", 16);
    h.add_u64(s.vertex_count());
    h.add_u64(s.triangle_count());
    h.add(s.positions.data(), 4 * s.positions.size());
    h.add(s.triangles.data(), 4 * s.triangles.size());
    h.add_u64(s.fields.size());
    for (const Field& f : s.fields) {
        h.add_u64(f.name.size());
        h.add(f.name.data(), f.name.size());
        h.add_u64(uint64_t(f.components));
        h.add(f.values.data(), 4 * f.values.size());
        if (kinds) h.add_u64(uint64_t(f.kind));
    }
    return h.hex();
}

} // namespace ddsimp::protocol
