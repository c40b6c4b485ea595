// Framing: header layout, every header check, and splitting a byte stream into frames.
#include "ddsimp/protocol/frame.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>

namespace ddsimp::protocol {
namespace {

std::string header_bytes(const char magic[4], uint16_t version, uint16_t type, uint32_t length) {
    std::string h(magic, 4);
    h += char(version & 0xff), h += char(version >> 8);
    h += char(type & 0xff), h += char(type >> 8);
    for (int i = 0; i < 4; ++i) h += char((length >> (8 * i)) & 0xff);
    return h;
}

const unsigned char* bytes(const std::string& s) {
    return reinterpret_cast<const unsigned char*>(s.data());
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const FrameError& e) {
        return e.what();
    }
    return "no error";
}

// The layout written by hand: "DDSP", version 1, type 30 (REQUEST), length 0x01020304, all LE.
TEST(Frame, HeaderLayout) {
    unsigned char h[kHeaderBytes];
    write_header(h, v1::REQUEST, 0x01020304);
    const unsigned char expected[] = {'D', 'D', 'S', 'P', 1, 0, 30, 0, 4, 3, 2, 1};
    EXPECT_EQ(0, std::memcmp(h, expected, kHeaderBytes));
    const FrameHeader read = read_header(h, 0x01020304);
    EXPECT_EQ(read.type, v1::REQUEST);
    EXPECT_EQ(read.length, 0x01020304u);
}

TEST(Frame, EveryHeaderCheckSaysWhatFailed) {
    EXPECT_NE(message_of([] {
                  read_header(bytes(header_bytes("HTTP", 1, 1, 0)), 100);
              }).find("not a ddsimp frame"),
              std::string::npos);
    EXPECT_NE(message_of([] {
                  read_header(bytes(header_bytes("DDSP", 2, 1, 0)), 100);
              }).find("protocol version 2 is not supported"),
              std::string::npos);
    EXPECT_NE(message_of([] {
                  read_header(bytes(header_bytes("DDSP", 1, 999, 0)), 100);
              }).find("unknown message type 999"),
              std::string::npos);
    EXPECT_NE(message_of([] {
                  read_header(bytes(header_bytes("DDSP", 1, 0, 0)), 100);
              }).find("unknown message type 0"),
              std::string::npos);
    EXPECT_EQ(message_of([] { read_header(bytes(header_bytes("DDSP", 1, 21, 101)), 100); }),
              "a UPLOAD_CHUNK frame of 101 bytes is over the limit of 100 bytes");
    EXPECT_EQ(message_of([] { read_header(bytes(header_bytes("DDSP", 1, 21, 100)), 100); }),
              "no error");
}

TEST(Frame, EncodeAndParseARequest) {
    v1::Request r;
    r.set_request_id(7);
    r.set_surface("abc");
    r.add_keep(0.5f);
    r.add_keep(0.1f);
    const std::string frame = encode_frame(r);
    ASSERT_EQ(frame.size(), kHeaderBytes + r.ByteSizeLong());
    const Frame f = decode_single_frame(frame, 1 << 20);
    const v1::Request back = parse_payload<v1::Request>(f);
    EXPECT_EQ(back.request_id(), 7u);
    EXPECT_EQ(back.surface(), "abc");
    ASSERT_EQ(back.keep_size(), 2);
    EXPECT_EQ(back.keep(1), 0.1f);
    EXPECT_EQ(message_of([&] { parse_payload<v1::Hello>(f); }),
              "expected a HELLO message, got REQUEST");
}

// A chunk written as head + data (no copy of the data into the message) is byte for byte the
// frame protobuf itself serializes with the data set, for sizes whose length varint is 1..3 bytes.
TEST(Frame, ChunkHeadFollowedByItsDataEqualsTheWholeFrame) {
    for (size_t n :
         {size_t(0), size_t(1), size_t(127), size_t(128), size_t(300), size_t(1) << 20}) {
        std::string data(n, '\0');
        for (size_t i = 0; i < n; ++i) data[i] = char(i * 31 + 7);
        v1::MeshChunk chunk;
        chunk.set_request_id(0x1234567890);
        chunk.set_level(3);
        chunk.set_offset(1u << 20);
        const std::string head = encode_frame_head(chunk, v1::MeshChunk::kDataFieldNumber, n);
        chunk.set_data(data);
        EXPECT_EQ(head + data, encode_frame(chunk)) << n << " bytes";
        EXPECT_EQ(parse_payload<v1::MeshChunk>(decode_single_frame(head + data, 2u << 20)).data(),
                  data);
    }
}

TEST(Frame, APayloadThatDoesNotParseIsAnError) {
    std::string frame = header_bytes("DDSP", 1, v1::REQUEST, 3) + "\xff\xff\xff";
    const Frame f = decode_single_frame(frame, 100);
    EXPECT_EQ(message_of([&] { parse_payload<v1::Request>(f); }),
              "a REQUEST message of 3 bytes does not parse");
}

TEST(Frame, SingleFrameMustBeExactlyOne) {
    v1::Ping p;
    p.set_nonce(42);
    const std::string frame = encode_frame(p);
    EXPECT_NE(message_of([&] { decode_single_frame(frame + "x", 100); }).find("carries"),
              std::string::npos);
    EXPECT_NE(message_of([&] {
                  decode_single_frame(frame.substr(0, frame.size() - 1), 100);
              }).find("carries"),
              std::string::npos);
    EXPECT_NE(message_of([&] { decode_single_frame("DDS", 100); }).find("shorter than a frame"),
              std::string::npos);
}

// Three frames fed one byte at a time come out whole, in order, each exactly once.
TEST(Frame, DecoderSplitsAStreamFedByteByByte) {
    std::string stream;
    for (uint64_t n = 1; n <= 3; ++n) {
        v1::Ping p;
        p.set_nonce(n * 1000);
        stream += encode_frame(p);
    }
    FrameDecoder decoder(100);
    std::vector<uint64_t> nonces;
    for (char c : stream) {
        decoder.feed(std::string_view(&c, 1));
        while (auto f = decoder.next()) nonces.push_back(parse_payload<v1::Ping>(*f).nonce());
    }
    EXPECT_EQ(nonces, (std::vector<uint64_t>{1000, 2000, 3000}));
    EXPECT_EQ(decoder.buffered(), 0u);
}

// An oversized header is refused as soon as its 12 bytes are in, before the payload arrives.
TEST(Frame, DecoderRefusesAnOversizedFrameFromItsHeader) {
    FrameDecoder decoder(1000);
    decoder.feed(header_bytes("DDSP", 1, v1::UPLOAD_CHUNK, 0xffffffff));
    EXPECT_THROW(decoder.next(), FrameError);
}

} // namespace
} // namespace ddsimp::protocol
