#include "surface_file.h"

#include "ddsimp/protocol/mesh_codec.h"
#include "ddsimp/v1/ddsimp.pb.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

namespace ddsimp::server {
namespace {

constexpr char kMagic[] = "DDSURF2\n";         // the header's fields carry their ranges
constexpr char kMagicNoRanges[] = "DDSURF1\n"; // written before ranges were
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

struct ParsedHeader {
    v1::UploadBegin header;
    bool ranges = false;
    size_t body = 0; // where the blob starts
};

// The magic, the header length and the header of a file whose first bytes are `prefix` (at least
// kMagicBytes + 4 of them); `read_more(n)` gives the next n bytes of the file after them.
template <class ReadMore>
ParsedHeader parse_header(const std::string& prefix, ReadMore read_more,
                          const std::filesystem::path& path) {
    const auto fail = [&](const std::string& what) {
        return SurfaceFileError(path.string() + ": " + what);
    };
    ParsedHeader out;
    if (prefix.size() < kMagicBytes + 4) throw fail("not a ddsimp surface file");
    if (prefix.compare(0, kMagicBytes, kMagic) == 0)
        out.ranges = true;
    else if (prefix.compare(0, kMagicBytes, kMagicNoRanges) != 0)
        throw fail("not a ddsimp surface file");
    uint32_t header_bytes = 0;
    for (int i = 0; i < 4; ++i)
        header_bytes |= uint32_t(static_cast<unsigned char>(prefix[kMagicBytes + i])) << (8 * i);
    const std::string header = read_more(size_t(header_bytes));
    if (header.size() != header_bytes) throw fail("truncated header");
    if (!out.header.ParseFromString(header)) throw fail("the header does not parse");
    out.body = kMagicBytes + 4 + size_t(header_bytes);
    return out;
}

protocol::BlobLayout layout_of(const v1::UploadBegin& header) {
    protocol::BlobLayout layout;
    layout.vertex_count = header.vertex_count();
    layout.triangle_count = header.triangle_count();
    for (const v1::FieldInfo& f : header.fields())
        layout.fields.push_back(protocol::field_spec_of(f));
    layout.section_bytes =
        protocol::raw_mesh_sections(layout.vertex_count, layout.triangle_count, layout.fields);
    return layout;
}

} // namespace

std::string encode_surface_file(const std::string& name, const Surface& surface) {
    v1::UploadBegin header;
    header.set_name(name);
    header.set_vertex_count(surface.vertex_count());
    header.set_triangle_count(surface.triangle_count());
    for (const Field& f : surface.fields) {
        v1::FieldInfo* info = header.add_fields();
        protocol::set_field_info(*info, {f.name, uint32_t(f.components), f.kind});
        if (!f.values.empty()) {
            const auto [lo, hi] = std::minmax_element(f.values.begin(), f.values.end());
            info->set_min(*lo);
            info->set_max(*hi);
        }
    }
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
    const ParsedHeader parsed = parse_header(
        bytes.substr(0, kMagicBytes + 4),
        [&](size_t n) { return bytes.substr(std::min(bytes.size(), kMagicBytes + 4), n); }, path);
    try {
        return {parsed.header.name(),
                protocol::decode_mesh(std::string_view(bytes).substr(parsed.body),
                                      layout_of(parsed.header))};
    } catch (const protocol::BlobError& e) {
        throw SurfaceFileError(path.string() + ": " + e.what());
    }
}

SurfaceFileHeader read_surface_header(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SurfaceFileError(system_error("cannot open", path));
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw SurfaceFileError(path.string() + ": " + ec.message());
    const auto read = [&](size_t n) { // never more than the file has, whatever a header says
        std::string out(std::min<uintmax_t>(n, size), '\0');
        in.read(out.data(), std::streamsize(out.size()));
        out.resize(size_t(in.gcount()));
        return out;
    };
    const ParsedHeader parsed = parse_header(read(kMagicBytes + 4), read, path);
    const v1::UploadBegin& h = parsed.header;
    SurfaceFileHeader out;
    out.name = h.name();
    out.vertices = h.vertex_count();
    out.triangles = h.triangle_count();
    out.ranges = parsed.ranges;
    for (const v1::FieldInfo& f : h.fields())
        out.fields.push_back(
            {f.name(), int(f.components()), protocol::field_spec_of(f).kind, f.min(), f.max()});
    try {
        const protocol::BlobLayout layout = layout_of(h);
        std::vector<protocol::FieldSpec> fields;
        for (const v1::FieldInfo& f : h.fields()) fields.push_back(protocol::field_spec_of(f));
        out.blob_bytes = protocol::raw_mesh_bytes(out.vertices, out.triangles, fields);
    } catch (const protocol::BlobError& e) {
        throw SurfaceFileError(path.string() + ": " + e.what());
    }
    if (size != parsed.body + out.blob_bytes)
        throw SurfaceFileError(path.string() + ": " + std::to_string(size) +
                               " bytes, but its header announces " +
                               std::to_string(parsed.body + out.blob_bytes));
    return out;
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
