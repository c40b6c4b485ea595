#include "surface_file.h"

#include "ddsimp/protocol/mesh_codec.h"
#include "ddsimp/v1/ddsimp.pb.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

namespace ddsimp::server {
namespace {

constexpr char kMagic[] = "DDSURF1\n";
constexpr size_t kMagicBytes = 8;

std::string system_error(const std::string& what, const std::filesystem::path& path) {
    return what + " " + path.string() + ": " + std::strerror(errno);
}

void write_all(int fd, const std::string& bytes, const std::filesystem::path& path) {
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw SurfaceFileError(system_error("cannot write", path));
        done += size_t(n);
    }
}

} // namespace

std::string encode_surface_file(const std::string& name, const Surface& surface) {
    v1::UploadBegin header;
    header.set_name(name);
    header.set_vertex_count(surface.vertex_count());
    header.set_triangle_count(surface.triangle_count());
    for (const protocol::FieldSpec& f : protocol::field_specs(surface))
        protocol::set_field_info(*header.add_fields(), f);
    const protocol::EncodedBlob blob = protocol::encode_mesh(surface, v1::RAW);
    header.set_total_bytes(blob.bytes.size());
    const std::string h = header.SerializeAsString();
    std::string out(kMagic, kMagicBytes);
    for (int i = 0; i < 4; ++i) out += char((h.size() >> (8 * i)) & 0xff);
    out += h;
    out += blob.bytes;
    return out;
}

SurfaceFile read_surface_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SurfaceFileError(system_error("cannot open", path));
    const std::string bytes{std::istreambuf_iterator<char>(in), {}};
    const auto fail = [&](const std::string& what) {
        return SurfaceFileError(path.string() + ": " + what);
    };
    if (bytes.size() < kMagicBytes + 4 || bytes.compare(0, kMagicBytes, kMagic) != 0)
        throw fail("not a ddsimp surface file");
    uint32_t header_bytes = 0;
    for (int i = 0; i < 4; ++i)
        header_bytes |= uint32_t(static_cast<unsigned char>(bytes[kMagicBytes + i])) << (8 * i);
    const size_t body = kMagicBytes + 4 + size_t(header_bytes);
    if (body > bytes.size()) throw fail("truncated header");
    v1::UploadBegin header;
    if (!header.ParseFromArray(bytes.data() + kMagicBytes + 4, int(header_bytes)))
        throw fail("the header does not parse");
    protocol::BlobLayout layout;
    layout.vertex_count = header.vertex_count();
    layout.triangle_count = header.triangle_count();
    for (const v1::FieldInfo& f : header.fields())
        layout.fields.push_back(protocol::field_spec_of(f));
    try {
        layout.section_bytes =
            protocol::raw_mesh_sections(layout.vertex_count, layout.triangle_count, layout.fields);
        return {header.name(), protocol::decode_mesh(std::string_view(bytes).substr(body), layout)};
    } catch (const protocol::BlobError& e) {
        throw fail(e.what());
    }
}

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
    const std::filesystem::path tmp = path.string() + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw SurfaceFileError(system_error("cannot create", tmp));
    try {
        write_all(fd, bytes, tmp);
        if (::fsync(fd) != 0) throw SurfaceFileError(system_error("cannot flush", tmp));
    } catch (...) {
        ::close(fd);
        ::unlink(tmp.c_str());
        throw;
    }
    ::close(fd);
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = system_error("cannot rename to", path);
        ::unlink(tmp.c_str());
        throw SurfaceFileError(reason);
    }
    // The rename is durable once the directory is flushed.
    const int dir = ::open(path.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        ::fsync(dir);
        ::close(dir);
    }
}

} // namespace ddsimp::server
