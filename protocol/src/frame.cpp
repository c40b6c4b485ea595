#include "ddsimp/protocol/frame.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

#include <cstring>

namespace ddsimp::protocol {
namespace {

constexpr unsigned char kMagic[4] = {'D', 'D', 'S', 'P'};

void put_u16(unsigned char* out, uint16_t v) {
    out[0] = static_cast<unsigned char>(v);
    out[1] = static_cast<unsigned char>(v >> 8);
}
void put_u32(unsigned char* out, uint32_t v) {
    for (int i = 0; i < 4; ++i) out[i] = static_cast<unsigned char>(v >> (8 * i));
}
uint16_t get_u16(const unsigned char* in) {
    return uint16_t(in[0] | (in[1] << 8));
}
uint32_t get_u32(const unsigned char* in) {
    return uint32_t(in[0]) | uint32_t(in[1]) << 8 | uint32_t(in[2]) << 16 | uint32_t(in[3]) << 24;
}

} // namespace

std::string message_type_name(v1::MessageType type) {
    if (v1::MessageType_IsValid(type)) return v1::MessageType_Name(type);
    return "type " + std::to_string(int(type));
}

void write_header(unsigned char* out, v1::MessageType type, uint32_t length) {
    std::memcpy(out, kMagic, 4);
    put_u16(out + 4, kProtocolVersion);
    put_u16(out + 6, static_cast<uint16_t>(type));
    put_u32(out + 8, length);
}

FrameHeader read_header(const unsigned char* in, size_t max_frame_bytes) {
    if (std::memcmp(in, kMagic, 4) != 0)
        throw FrameError("not a ddsimp frame (the first four bytes are not \"DDSP\")");
    const uint16_t version = get_u16(in + 4);
    if (version != kProtocolVersion)
        throw FrameError("protocol version " + std::to_string(version) +
                         " is not supported (this side speaks version " +
                         std::to_string(kProtocolVersion) + ")");
    const uint16_t type = get_u16(in + 6);
    if (!v1::MessageType_IsValid(type) || type == v1::MESSAGE_TYPE_UNSPECIFIED)
        throw FrameError("unknown message type " + std::to_string(type));
    const uint32_t length = get_u32(in + 8);
    if (length > max_frame_bytes)
        throw FrameError("a " + message_type_name(v1::MessageType(type)) + " frame of " +
                         std::to_string(length) + " bytes is over the limit of " +
                         std::to_string(max_frame_bytes) + " bytes");
    return {v1::MessageType(type), length};
}

std::string encode_frame(v1::MessageType type, const google::protobuf::MessageLite& message) {
    const size_t length = message.ByteSizeLong();
    if (length > UINT32_MAX)
        throw FrameError("a " + message_type_name(type) + " message of " + std::to_string(length) +
                         " bytes does not fit in a frame");
    std::string frame(kHeaderBytes + length, '\0');
    auto* bytes = reinterpret_cast<unsigned char*>(frame.data());
    write_header(bytes, type, uint32_t(length));
    message.SerializeWithCachedSizesToArray(bytes + kHeaderBytes);
    return frame;
}

std::string encode_frame_head(v1::MessageType type, const google::protobuf::MessageLite& message,
                              int field_number, size_t field_bytes) {
    using google::protobuf::internal::WireFormatLite;
    using google::protobuf::io::CodedOutputStream;
    const uint32_t tag =
        WireFormatLite::MakeTag(field_number, WireFormatLite::WIRETYPE_LENGTH_DELIMITED);
    const size_t message_bytes = message.ByteSizeLong();
    // proto3 leaves an empty bytes field out.
    const size_t field_head = field_bytes == 0 ? 0
                                               : CodedOutputStream::VarintSize32(tag) +
                                                     CodedOutputStream::VarintSize64(field_bytes);
    const size_t length = message_bytes + field_head + field_bytes;
    if (length > UINT32_MAX)
        throw FrameError("a " + message_type_name(type) + " message of " + std::to_string(length) +
                         " bytes does not fit in a frame");
    std::string head(kHeaderBytes + message_bytes + field_head, '\0');
    auto* bytes = reinterpret_cast<unsigned char*>(head.data());
    write_header(bytes, type, uint32_t(length));
    bytes = message.SerializeWithCachedSizesToArray(bytes + kHeaderBytes);
    if (field_bytes > 0) {
        bytes = CodedOutputStream::WriteVarint32ToArray(tag, bytes);
        CodedOutputStream::WriteVarint64ToArray(field_bytes, bytes);
    }
    return head;
}

std::optional<Frame> FrameDecoder::next() {
    if (buffered() < kHeaderBytes) return std::nullopt;
    const auto* at = reinterpret_cast<const unsigned char*>(buffer_.data() + consumed_);
    const FrameHeader header = read_header(at, max_frame_bytes_);
    if (buffered() < kHeaderBytes + header.length) return std::nullopt;
    Frame frame{header.type, buffer_.substr(consumed_ + kHeaderBytes, header.length)};
    consumed_ += kHeaderBytes + header.length;
    // Drop consumed bytes once they are the larger part, so the buffer stays bounded.
    if (consumed_ > buffer_.size() / 2) {
        buffer_.erase(0, consumed_);
        consumed_ = 0;
    }
    return frame;
}

Frame decode_single_frame(std::string_view bytes, size_t max_frame_bytes) {
    if (bytes.size() < kHeaderBytes)
        throw FrameError("a message of " + std::to_string(bytes.size()) +
                         " bytes is shorter than a frame header");
    const FrameHeader header =
        read_header(reinterpret_cast<const unsigned char*>(bytes.data()), max_frame_bytes);
    if (bytes.size() != kHeaderBytes + header.length)
        throw FrameError("a " + message_type_name(header.type) + " frame says " +
                         std::to_string(header.length) + " payload bytes but carries " +
                         std::to_string(bytes.size() - kHeaderBytes));
    return {header.type, std::string(bytes.substr(kHeaderBytes))};
}

} // namespace ddsimp::protocol
